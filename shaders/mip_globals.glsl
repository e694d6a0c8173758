// mipcast piece: mip_globals
// fills: Base::Dec
// mode: augment
// Globals and helpers every mipcast shader shares: the ray's maximum of the
// normalised scalar (VTK's scale/bias applied), set in castRay() and read in
// finalizeRayCast(); conversions between raw texel values and VTK's
// normalised scalar; and the ray set-up of the Terminate::Init pieces
// (refusal, image_terminate, demip_two_pass_fetch).
float mc_rayMax;

// Whether the ray met missing data only, for hook pieces that start their rays at a transfer-function
// bound (they #define MC_MISSING_FLAG: *_hooks_blocks, amip_max_hooks, amip_min_hooks). Their value is
// then the bound's table end, which says nothing of that; missing_exit, missing_exit_above and
// foveated_missing_flag read the flag instead of comparing the value with the threshold.
bool mc_rayMissing = false;

// Normalised scalar (VTK's scale/bias) -> raw texel value.
float mcRaw(float normalised)
{
  return (normalised - in_volume_bias[0].r) / in_volume_scale[0].r;
}

// Raw texel value -> VTK's normalised scalar.
float mcNormalised(float raw)
{
  return raw * in_volume_scale[0].r + in_volume_bias[0].r;
}

// A running value (raw) that started at one of the transfer functions'
// bounds (lo: the floor, hi: the ceiling) and stopped at the other (the
// skipping hooks: *_hooks_blocks, amip_max_hooks, amip_min_hooks) -> the
// normalised value to colour: the tables' bottom (0.0) at or below the
// floor, their top (1.0) at or above the ceiling, where VTK's tables hold
// exactly the transfer functions' constant colours (the bound itself may lie
// between two table texels). A macro, not a function: a brick of a
// distributed volume redefines mcNormalised after this piece (global_cells,
// global_phase), and the hooks that use it come after that.
// (The bounds are handed the normalised values of the tables' ends, mcTableEnd below: 0 and 1 but for
// 8- and 16-bit integers.)
#define MC_BOUNDED_NORMALISED(raw, lo, hi) ((raw) <= (lo) ? mcTableEnd(0.0) : ((raw) >= (hi) ? mcTableEnd(1.0) : mcNormalised(raw)))

// Where VTK's transfer-function tables hold a normalised value s. VTK tabulates each function at n points,
// i / (n - 1) of the table's range (vtkColorTransferFunction::GetTable), into a texture whose texel i lies
// at (i + 0.5) / n, and reads it at s itself: the function half a table step off, -1/2 step at 0 to +1/2 at
// 1 (stock VTK's own lookups; under a window 3 % of the range wide up to 4 grey darker). mipcast's colour
// lookups read at mcAtTable instead: the function at s, interpolated between its tabulated points. Macros:
// the samplers are declared after this piece. u_mc_tableScale (scale, bias) first takes s to the value's
// place in the tables: (1, 0) but for 8- and 16-bit integers, whose s VTK computes for the value times
// 256/255 (65536/65535, ...; float_readout.table_coordinate).
float mcAtTable(float s, float texels)
{
  return (clamp(s * u_mc_tableScale.x + u_mc_tableScale.y, 0.0, 1.0) * (texels - 1.0) + 0.5) / texels;
}
// The normalised value s whose place in the tables is t (0: the data's minimum, 1: its maximum).
float mcTableEnd(float t)
{
  return (t - u_mc_tableScale.y) / u_mc_tableScale.x;
}
#define MC_COLOR_AT(s) vec4(mcAtTable((s), float(textureSize(in_colorTransferFunc_0[0], 0).x)))
#define MC_OPACITY_AT(s) vec4(mcAtTable((s), float(textureSize(in_opacityTransferFunc_0[0], 0).x)))

// (enters, leaves): the parameters (in units of dir from `from`) where the
// line from + s dir enters and leaves the box [lo, hi]; axes the line runs
// parallel to bound nothing (never divided by zero). The ray loops' exit
// (sampled_loop, amip_cell), a brick's whole-volume entry and ray
// (whole_ray_end, global_phase, global_cells) and a mended ray's set-up
// (ray_mend) all read their box so.
vec2 mcLineThroughBox(vec3 from, vec3 dir, vec3 lo, vec3 hi)
{
  vec3 parallel = vec3(equal(dir, vec3(0.0)));
  vec3 safe = mix(dir, vec3(1.0), parallel);
  vec3 toLow = (lo - from) / safe;
  vec3 toHigh = (hi - from) / safe;
  vec3 enters = mix(min(toLow, toHigh), vec3(-1.0e30), parallel);
  vec3 leaves = mix(max(toLow, toHigh), vec3(1.0e30), parallel);
  return vec2(max(max(enters.x, enters.y), enters.z), min(min(leaves.x, leaves.y), leaves.z));
}

// VTK starts each ray at its fragment's rasterised position on the box:
// where the pixel's line enters it or, while the camera's near plane cuts
// the box, on VTK's cap inside it. On a face met at a grazing angle (0.01 to
// 1 degree; nearer edge-on the ray_mend piece sets the ray up again) float
// rounding puts that position on the line but up to a tenth of the box
// deeper in (the ray skipped the box's first part: analytic MIP 0.055 of
// the range off; tests/edge_on_check.py sweep) or in front of the box. The
// ray loops (sampled_loop, amip_cell) move such a start to where its line
// enters the box, the jitter and the end kept: mcEntryShift(box, unit), for
// `box` = mcLineThroughBox(start, dir, ...) and `unit` the length of dir in
// texture units, is the ray parameter of that entry where it lies more than
// 1e-4 (texture units) from the start, else 0: every other start stays as
// it is, bit for bit. u_mc_entryMoves (MIPVolumeMapper._entry_moves): 0, no
// start moves (VTK caps the box: a cap start lies inside it); 1, only
// starts behind the entry move (the window draws with MSAA: VTK starts a
// silhouette pixel whose centre lies off the box on the face's plane, in
// front of the box, on purpose); 2, both; 0 too while no face is met at a
// sine below 0.1 (mipcast.mappers.mip.ENTRY_MOVES: no start lies off by
// 1e-4 there, and the test cost llvmpipe's analytic walk 4-7 % of a frame).
// A line missing the box: no move.
float mcEntryShift(vec2 box, float unit)
{
  if (u_mc_entryMoves < 0.5)
  {
    return 0.0;
  }
  float ahead = box.x * unit;
  bool moves = ahead < -1.0e-4 || (ahead > 1.0e-4 && u_mc_entryMoves > 1.5);  // (behind: 1 or 2)
  return moves && box.x <= box.y ? box.x : 0.0;
}

// A cast ray that draws nothing (clipped or cropped away, missing the
// volume): MC_DRAW_NOTHING(result) where it is found, in place of discard
// (mcDrawNothing() where the function goes on to its end anyway). It
// discards, unless mc_paintsNothing is set: the masked levels of
// content-adaptive foveation (foveated_skip_masked, foveated_skip_coarse)
// are drawn over coarser levels, which must not show through, so there the
// ray is marked mc_drawsNothing and returns `result` from the function it
// is in, and foveated_paint_beneath paints what lay beneath the volume
// instead (a caller of a function that can return so checks
// mc_drawsNothing).
bool mc_drawsNothing = false;
bool mc_paintsNothing = false;

void mcDrawNothing()
{
  if (!mc_paintsNothing)
  {
    discard;
  }
  mc_drawsNothing = true;
}

#define MC_DRAW_NOTHING(result) { mcDrawNothing(); return result; }

// A mipcast mapper that refuses to render (bad input, a limit exceeded; the
// reason goes to VTK's error output) sets u_mc_refused: no ray is cast and
// the volume draws nothing, rather than a wrong picture.
void mcRefuseIfAsked()
{
  if (u_mc_refused > 0.5)
  {
    discard;
  }
}

// Clipping planes, cropping box and slab (mipcast/mappers/clip_uniforms.py):
// u_mc_clipCount planes u_mc_clip0 .. u_mc_clip13, each (a, b, c, d) in
// texture coordinates, keeping the points p with a p.x + b p.y + c p.z + d
// >= 0 (separate vec4 uniforms, not an array: VTK 9.2's custom uniform
// arrays are not safe). mcClipRange narrows [lo, hi] of the ray
// p(s) = start + s * dir to the kept part (lo > hi: nothing is kept). Once
// per ray, never per sample.
void mcClipPlane(vec4 plane, vec3 start, vec3 dir, inout float lo, inout float hi)
{
  float at0 = dot(plane.xyz, start) + plane.w;
  float rate = dot(plane.xyz, dir);
  if (rate > 0.0)
  {
    lo = max(lo, -at0 / rate);
  }
  else if (rate < 0.0)
  {
    hi = min(hi, -at0 / rate);
  }
  else if (at0 < 0.0)
  {
    hi = -1.0e30;
  }
}

void mcClipRange(vec3 start, vec3 dir, inout float lo, inout float hi)
{
  if (u_mc_clipCount > 0) mcClipPlane(u_mc_clip0, start, dir, lo, hi);
  if (u_mc_clipCount > 1) mcClipPlane(u_mc_clip1, start, dir, lo, hi);
  if (u_mc_clipCount > 2) mcClipPlane(u_mc_clip2, start, dir, lo, hi);
  if (u_mc_clipCount > 3) mcClipPlane(u_mc_clip3, start, dir, lo, hi);
  if (u_mc_clipCount > 4) mcClipPlane(u_mc_clip4, start, dir, lo, hi);
  if (u_mc_clipCount > 5) mcClipPlane(u_mc_clip5, start, dir, lo, hi);
  if (u_mc_clipCount > 6) mcClipPlane(u_mc_clip6, start, dir, lo, hi);
  if (u_mc_clipCount > 7) mcClipPlane(u_mc_clip7, start, dir, lo, hi);
  if (u_mc_clipCount > 8) mcClipPlane(u_mc_clip8, start, dir, lo, hi);
  if (u_mc_clipCount > 9) mcClipPlane(u_mc_clip9, start, dir, lo, hi);
  if (u_mc_clipCount > 10) mcClipPlane(u_mc_clip10, start, dir, lo, hi);
  if (u_mc_clipCount > 11) mcClipPlane(u_mc_clip11, start, dir, lo, hi);
  if (u_mc_clipCount > 12) mcClipPlane(u_mc_clip12, start, dir, lo, hi);
  if (u_mc_clipCount > 13) mcClipPlane(u_mc_clip13, start, dir, lo, hi);
}

// VTK's ray bookkeeping (as at Terminate::Init) for a ray that ends at the
// window point `at` (0..1 in the image) and NDC depth ndcDepth.
void mcSetRayEnd(vec2 at, float ndcDepth)
{
  vec4 termination = vec4(at * 2.0 - 1.0, ndcDepth, 1.0);
  termination = ip_inverseTextureDataAdjusted * in_inverseVolumeMatrix[0] *
                in_inverseModelViewMatrix * in_inverseProjectionMatrix * termination;
  g_rayTermination = termination.xyz / termination.w;
  g_dataPos = g_rayOrigin;
  g_terminatePos = g_rayTermination;
  g_terminatePointMax = length(g_terminatePos.xyz - g_dataPos.xyz) / length(g_dirStep);
  g_currentT = 0.0;
}

// mcSetRayEnd for a ray ending at the window depth sceneDepth (0..1, as the
// depth buffer holds it; 1: the far plane).
void mcSetSceneRayEnd(vec2 at, float sceneDepth)
{
  mcSetRayEnd(at, (2.0 * sceneDepth - (gl_DepthRange.near + gl_DepthRange.far)) / gl_DepthRange.diff);
}
