// mipcast piece: foveated_refine_pass
// fills: CompositeMask::Dec
// mode: augment
// Content-adaptive foveation, the refinement test once per texel of the
// deciding level (mipcast.core.content_adaptive.refinement_test): the
// fragment code of its own small pass (not installed in the ray caster;
// mipcast.mappers.refine_pass compiles it into VTK's full-screen quad
// template, after the deciding level is drawn). One fragment per texel of
// that level's grid (u_mc_fovCoarseW x u_mc_fovCoarseH, bottom row first)
// writes, for the texel's 3 x 3 neighbourhood (edges clamped), read from
// the viewport's picture after that level and before the frame's first
// level was drawn (u_mc_fovAfter/Before, RGBA8, the viewport's size,
// bottom row first):
//   red   1 where the grey (largest channel) spans at least
//         u_mc_fovEdgeMin grey levels (more than the tolerance),
//   green 1 where a texel differs from the picture before (structure
//         above the floor), where u_mc_fovBound (R8, the grid's size,
//         bottom row first) is set (the data says a full-quality ray in the
//         texel's cell may meet structure the coarse rays missed:
//         mipcast.core.structure_bound), or everywhere when u_mc_fovWholeFovea is 1
//         (a content level deciding acuity's coarsest level, which casts
//         the whole fovea).
// A finer level's ray then reads its nearest texel once
// (foveated_coarse_dec's mcFovRefine): red, or green inside the fovea --
// the rule mipcast.core.content_adaptive.refinement_mask defines.
uniform sampler2D u_mc_fovAfter;
uniform sampler2D u_mc_fovBefore;
uniform sampler2D u_mc_fovBound;
uniform int u_mc_fovCoarseW;
uniform int u_mc_fovCoarseH;
uniform int u_mc_fovViewW;
uniform int u_mc_fovViewH;
uniform float u_mc_fovEdgeMin;
uniform float u_mc_fovWholeFovea;

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

// Whether the texel at viewport pixel ``at`` differs from the picture before the frame's first level.
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

// (edge, structure, 0, 1) of the coarse texel at (column, top-first row); ``bound``: structure whatever the picture.
vec4 mcFovRefineTexel(int cx, int cy, bool bound)
{
  ivec3 xs = ivec3(mcFovCoarseX(cx - 1), mcFovCoarseX(cx), mcFovCoarseX(cx + 1));
  ivec3 ys = ivec3(mcFovCoarseY(cy - 1), mcFovCoarseY(cy), mcFovCoarseY(cy + 1));
  bool structure = mcFovStructure(ivec2(xs.y, ys.y)) || mcFovStructure(ivec2(xs.x, ys.y))
                   || mcFovStructure(ivec2(xs.z, ys.y)) || mcFovStructure(ivec2(xs.y, ys.x))
                   || mcFovStructure(ivec2(xs.y, ys.z)) || mcFovStructure(ivec2(xs.x, ys.x))
                   || mcFovStructure(ivec2(xs.z, ys.x)) || mcFovStructure(ivec2(xs.x, ys.z))
                   || mcFovStructure(ivec2(xs.z, ys.z));
  vec3 top = vec3(mcFovValue(ivec2(xs.x, ys.x)), mcFovValue(ivec2(xs.y, ys.x)), mcFovValue(ivec2(xs.z, ys.x)));
  vec3 middle = vec3(mcFovValue(ivec2(xs.x, ys.y)), mcFovValue(ivec2(xs.y, ys.y)), mcFovValue(ivec2(xs.z, ys.y)));
  vec3 bottom = vec3(mcFovValue(ivec2(xs.x, ys.z)), mcFovValue(ivec2(xs.y, ys.z)), mcFovValue(ivec2(xs.z, ys.z)));
  vec3 high = max(top, max(middle, bottom));
  vec3 low = min(top, min(middle, bottom));
  bool edge = max(high.x, max(high.y, high.z)) - min(low.x, min(low.y, low.z)) >= u_mc_fovEdgeMin;
  return vec4(edge ? 1.0 : 0.0, (structure || bound || u_mc_fovWholeFovea > 0.5) ? 1.0 : 0.0, 0.0, 1.0);
}

// The pass's body: the coarse texel of the fragment at ``at`` (the quad's
// texture coordinate, 0..1 over the grid, bottom row first: a fragment
// centre is (i + 0.5) / size, so floor(at * size) is its texel exactly).
vec4 mcFovRefinePass(vec2 at)
{
  int cx = clamp(int(floor(at.x * float(u_mc_fovCoarseW))), 0, u_mc_fovCoarseW - 1);
  int rowUp = clamp(int(floor(at.y * float(u_mc_fovCoarseH))), 0, u_mc_fovCoarseH - 1);
  bool bound = texelFetch(u_mc_fovBound, ivec2(cx, rowUp), 0).r > 0.5;
  return mcFovRefineTexel(cx, u_mc_fovCoarseH - 1 - rowUp, bound);
}
