// mipcast piece: foveated_coarse_dec
// fills: CompositeMask::Dec
// mode: augment
// Content-adaptive foveation with the refinement mask built on the GPU
// (foveated_skip_coarse): the refinement test of every texel of the
// deciding level's grid (mipcast.core.content_adaptive.decided_by),
// computed once per frame by the refine pass (foveated_refine_pass, from
// the viewport's picture after that level and before the frame's first
// level was drawn): RGBA8, one texel per deciding texel (bottom row
// first), red 1 where the grey of its 3 x 3 neighbourhood spans more than
// the tolerance, green 1 where that neighbourhood holds structure above
// the floor. Bound by the foveated mapper.
uniform sampler2D u_mc_fovRefine;
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

// mipcast.core.content_adaptive.refinement_mask for the ray at (column,
// top-first row) of this level's grid (u_mc_fovLevelW x u_mc_fovLevelH):
// true when the grey (largest channel) of the nearest deciding texel's
// 3 x 3 neighbourhood (edges clamped) spans more than the tolerance, or,
// inside the fovea (inFovea: mcFovInFovea), when that neighbourhood
// differs from the picture before the frame's first level was drawn
// (structure above the floor) -- one fetch of the refine pass's texel.
bool mcFovRefine(int column, int row, bool inFovea)
{
  int cx = min(((2 * column + 1) * u_mc_fovCoarseW) / (2 * u_mc_fovLevelW), u_mc_fovCoarseW - 1);
  int cy = min(((2 * row + 1) * u_mc_fovCoarseH) / (2 * u_mc_fovLevelH), u_mc_fovCoarseH - 1);
  vec4 refine = texelFetch(u_mc_fovRefine, ivec2(cx, u_mc_fovCoarseH - 1 - cy), 0);
  return refine.r > 0.5 || (inFovea && refine.g > 0.5);
}

// A masked level (content-adaptive density) is drawn over coarser levels:
// a ray it casts is drawn over the picture that lay beneath the volume
// before the frame's first level (u_mc_fovBeneath, RGBA8, the viewport's
// size u_mc_fovViewSize, bottom row first), and a cast ray that draws
// nothing paints that picture (foveated_paint_beneath); u_mc_fovPaintBeneath 0
// (a float readout): neither, such a ray draws nothing. (Those two are
// custom uniforms, which VTK declares.)
uniform sampler2D u_mc_fovBeneath;
