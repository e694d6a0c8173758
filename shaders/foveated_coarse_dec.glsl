// mipcast piece: foveated_coarse_dec
// fills: CompositeMask::Dec
// mode: augment
// Content-adaptive foveation with the refinement mask built on the GPU
// (foveated_skip_coarse): the viewport's picture after and before the
// coarsest level was drawn, copied on the GPU into textures of the
// viewport's size (bottom row first, RGBA8). Bound by the foveated mapper.
uniform sampler2D u_mc_fovAfter;
uniform sampler2D u_mc_fovBefore;
// The fovea on this level's grid, as the CPU definition decides it (float64
// eccentricity of the texel centre below the acuity schedule's start):
// texel (row, 0), top row first, holds the row's columns [first, end)
// inside it (mipcast.core.content_adaptive.fovea_spans).
uniform sampler2D u_mc_fovFovea;

// Whether this level's ray (column, top-first row) lies in the fovea.
bool mcFovInFovea(int column, int row)
{
  vec2 span = texelFetch(u_mc_fovFovea, ivec2(row, 0), 0).rg;
  return float(column) >= span.x && float(column) < span.y;
}

// The viewport pixel (bottom row first) the CPU definition
// (mipcast.core.content_adaptive.coarse_texels) reads for coarse texel
// (column, top-first row): min(floor((i + 0.5) * size / grid), size - 1),
// in integers, exact.
ivec2 mcFovCoarsePixel(int column, int row)
{
  int x = min(((2 * column + 1) * u_mc_fovViewW) / (2 * u_mc_fovCoarseW), u_mc_fovViewW - 1);
  int y = min(((2 * row + 1) * u_mc_fovViewH) / (2 * u_mc_fovCoarseH), u_mc_fovViewH - 1);
  return ivec2(x, u_mc_fovViewH - 1 - y);
}

// Grey levels 0..255 of an RGBA8 texel's channels.
vec3 mcFovGrey(vec4 texel)
{
  return floor(texel.rgb * 255.0 + 0.5);
}

// mipcast.core.content_adaptive.refinement_masks for the ray at (column,
// top-first row) of this level's grid (u_mc_fovLevelW x u_mc_fovLevelH):
// true when the coarse grey (largest channel) of the nearest coarse
// texel's 3 x 3 neighbourhood (edges clamped) spans more than the
// tolerance (at least u_mc_fovEdgeMin grey levels), or, inside the fovea
// (inFovea: mcFovInFovea), when a texel of that neighbourhood differs from the picture
// before the coarsest level was drawn (structure above the floor).
bool mcFovRefine(int column, int row, bool inFovea)
{
  int cx = min(((2 * column + 1) * u_mc_fovCoarseW) / (2 * u_mc_fovLevelW), u_mc_fovCoarseW - 1);
  int cy = min(((2 * row + 1) * u_mc_fovCoarseH) / (2 * u_mc_fovLevelH), u_mc_fovCoarseH - 1);
  float high = -1.0;
  float low = 256.0;
  bool structure = false;
  for (int dy = -1; dy <= 1; ++dy)
  {
    for (int dx = -1; dx <= 1; ++dx)
    {
      ivec2 at = mcFovCoarsePixel(clamp(cx + dx, 0, u_mc_fovCoarseW - 1),
                                  clamp(cy + dy, 0, u_mc_fovCoarseH - 1));
      vec3 after = mcFovGrey(texelFetch(u_mc_fovAfter, at, 0));
      float grey = max(after.r, max(after.g, after.b));
      high = max(high, grey);
      low = min(low, grey);
      if (inFovea)
      {
        vec3 before = mcFovGrey(texelFetch(u_mc_fovBefore, at, 0));
        structure = structure || any(notEqual(after, before));
      }
    }
  }
  return (high - low) >= u_mc_fovEdgeMin || structure;
}
