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

// The viewport pixel column / row (bottom row first) the CPU definition
// (mipcast.core.content_adaptive.coarse_texels) reads for coarse texel
// column / top-first row i (clamped to the grid first):
// min(floor((i + 0.5) * size / grid), size - 1), in integers, exact.
int mcFovCoarseX(int column)
{
  column = clamp(column, 0, u_mc_fovCoarseW - 1);
  return min(((2 * column + 1) * u_mc_fovViewW) / (2 * u_mc_fovCoarseW), u_mc_fovViewW - 1);
}

int mcFovCoarseY(int row)
{
  row = clamp(row, 0, u_mc_fovCoarseH - 1);
  return u_mc_fovViewH - 1 - min(((2 * row + 1) * u_mc_fovViewH) / (2 * u_mc_fovCoarseH), u_mc_fovViewH - 1);
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
// Whether the coarse texel at viewport pixel ``at`` differs from the picture before the coarsest level.
bool mcFovStructure(ivec2 at)
{
  return any(notEqual(mcFovGrey(texelFetch(u_mc_fovAfter, at, 0)), mcFovGrey(texelFetch(u_mc_fovBefore, at, 0))));
}

// The coarse grey (largest channel) at viewport pixel ``at``.
float mcFovValue(ivec2 at)
{
  vec3 after = mcFovGrey(texelFetch(u_mc_fovAfter, at, 0));
  return max(after.r, max(after.g, after.b));
}

bool mcFovRefine(int column, int row, bool inFovea)
{
  int cx = min(((2 * column + 1) * u_mc_fovCoarseW) / (2 * u_mc_fovLevelW), u_mc_fovCoarseW - 1);
  int cy = min(((2 * row + 1) * u_mc_fovCoarseH) / (2 * u_mc_fovLevelH), u_mc_fovCoarseH - 1);
  ivec3 xs = ivec3(mcFovCoarseX(cx - 1), mcFovCoarseX(cx), mcFovCoarseX(cx + 1));
  ivec3 ys = ivec3(mcFovCoarseY(cy - 1), mcFovCoarseY(cy), mcFovCoarseY(cy + 1));
  // structure anywhere in the neighbourhood (fovea only): cast, whatever the edges say
  // (the 3 x 3 neighbourhood written out: || stops at the first texel with structure)
  if (inFovea
      && (mcFovStructure(ivec2(xs.y, ys.y)) || mcFovStructure(ivec2(xs.x, ys.y))
          || mcFovStructure(ivec2(xs.z, ys.y)) || mcFovStructure(ivec2(xs.y, ys.x))
          || mcFovStructure(ivec2(xs.y, ys.z)) || mcFovStructure(ivec2(xs.x, ys.x))
          || mcFovStructure(ivec2(xs.z, ys.x)) || mcFovStructure(ivec2(xs.x, ys.z))
          || mcFovStructure(ivec2(xs.z, ys.z))))
  {
    return true;
  }
  vec3 top = vec3(mcFovValue(ivec2(xs.x, ys.x)), mcFovValue(ivec2(xs.y, ys.x)), mcFovValue(ivec2(xs.z, ys.x)));
  vec3 middle = vec3(mcFovValue(ivec2(xs.x, ys.y)), mcFovValue(ivec2(xs.y, ys.y)), mcFovValue(ivec2(xs.z, ys.y)));
  vec3 bottom = vec3(mcFovValue(ivec2(xs.x, ys.z)), mcFovValue(ivec2(xs.y, ys.z)), mcFovValue(ivec2(xs.z, ys.z)));
  vec3 high = max(top, max(middle, bottom));
  vec3 low = min(top, min(middle, bottom));
  return max(high.x, max(high.y, high.z)) - min(low.x, min(low.y, low.z)) >= u_mc_fovEdgeMin;
}
