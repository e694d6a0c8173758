// mipcast piece: global_phase
// fills: BinaryMask::Dec
// mode: augment
// One brick of a distributed volume (mipcast.distributed): the sampled loop
// takes the WHOLE volume's samples, at positions bit for bit the same on
// every rank whatever the split. Each pixel's ray is computed in the whole volume's
// absolute point-index space from uniforms that are the same on every rank
// (mipcast.distributed.ray_uniforms: the ray's point on a plane through
// the volume, affine in the pixel's NDC, and the eye or the parallel
// direction; the whole and the brick's index boxes, the spacing and the
// sample distance), not from the brick's own rasterised texture
// coordinates. As in VTK's loop for the whole volume, sample k sits at the
// whole ray's start + (1 + k) steps, k = 0 .. floor(steps from the first
// sample to the box's exit); the start is the whole box's entry, or where
// the camera is inside the volume (its near plane cuts the box) VTK's
// near-plane cap when the ray crosses it beyond the entry (u_mc_rayCap: the
// cap n . p = w in point indices, camera_rays.near_cap; n = 0: no cap). mcGlobalSample(k) interpolates it by hand
// (texelFetch of the cell's 8 points, exact cell index and fractions; under the
// volume property's nearest-neighbour interpolation, u_mc_nearest, the nearest of them),
// so the value does not depend on the brick's texture size; a brick takes
// the samples whose cell (clamped to the whole box) lies in its extent:
// every cell lies in a brick (bricks share a point layer), a sample on a
// shared face belongs to the cell above it. Samples of cells elsewhere
// read -1e30 (no sample). mcGlobalNormalised is VTK's normalisation
// with the WHOLE volume's range, so that the readouts of all ranks are on
// one grid: u_mc_globalNorm = (1, scale, bias) maps the raw texel value
// directly (float and 8-bit data, whose texels hold the data as they are:
// the same bits on every rank), (2, a, b) re-normalises the brick's
// normalised scalar (other types), (0, ..) leaves VTK's.
#define MC_GLOBAL_PHASE

vec3 mc_gEntry;  // the whole ray's start (box entry or near-plane cap), absolute point index
vec3 mc_gStep;   // one sample step, point-index units

float mcGlobalNormalised(float raw)
{
  if (u_mc_globalNorm.x > 1.5)
  {
    return mcNormalised(raw) * u_mc_globalNorm.y + u_mc_globalNorm.z;
  }
  return u_mc_globalNorm.x > 0.5 ? raw * u_mc_globalNorm.y + u_mc_globalNorm.z : mcNormalised(raw);
}

void mcGlobalPhase(float stepsInBox, inout vec3 base, inout int first, inout int count)
{
  vec2 mc_ndc = 2.0 * gl_FragCoord.xy * in_inverseWindowSize - 1.0;
  vec3 mc_point = u_mc_rayPoint0 + mc_ndc.x * u_mc_rayPointX + mc_ndc.y * u_mc_rayPointY;
  vec3 mc_dir = mix(u_mc_rayDirection, mc_point - u_mc_rayEye.xyz, u_mc_rayEye.w);
  mc_gStep = mc_dir * (u_mc_rayStep / length(mc_dir * u_mc_raySpacing));
  vec2 mc_whole = mcLineThroughBox(mc_point, mc_gStep, u_mc_wholeLo, u_mc_wholeHi);
  float mc_sIn = mc_whole.x;
  float mc_sOut = mc_whole.y;
  // the camera inside the volume: the cap's steps past the box entry (0 before it, or without a cap)
  float mc_capAlong = dot(u_mc_rayCap.xyz, mc_gStep);
  float mc_capShift = mc_capAlong > 0.0 ?
    max((u_mc_rayCap.w - dot(u_mc_rayCap.xyz, mc_point)) / mc_capAlong - mc_sIn, 0.0) : 0.0;
  mc_sIn += mc_capShift;
  mc_gEntry = mc_point + mc_sIn * mc_gStep;
  // the whole volume's sample 0 in this brick's texture coordinates (for clipping)
  float mc_in = mcLineThroughBox(g_dataPos, g_dirStep, u_mc_globalTexMin, u_mc_globalTexMax).x;
  base = g_dataPos + (mc_in + mc_capShift + 1.0) * g_dirStep;
  if (mc_sIn > mc_sOut)
  {
    first = 0;
    count = 0;  // the ray misses the whole box (or leaves it before the cap)
    return;
  }
  int mc_last = int(floor(max(mc_sOut - mc_sIn - 1.0, 0.0)));
  // this brick's part of the ray, one sample wider each side (the cell test decides)
  vec2 mc_brick = mcLineThroughBox(mc_gEntry, mc_gStep, u_mc_brickLo, u_mc_brickHi);
  float mc_bIn = mc_brick.x;
  float mc_bOut = mc_brick.y;
  first = mc_last == 0 ? 0 : int(clamp(floor(mc_bIn) - 2.0, 0.0, float(mc_last + 1)));
  count = mc_last == 0 ? 1 : int(clamp(ceil(mc_bOut) + 1.0, 0.0, float(mc_last + 1)));
}

float mcGlobalSample(int k)
{
  vec3 mc_p = clamp(mc_gEntry + float(k + 1) * mc_gStep, u_mc_wholeLo, u_mc_wholeHi);
  vec3 mc_c = max(min(floor(mc_p), u_mc_wholeHi - 1.0), u_mc_wholeLo);
  vec3 mc_c1 = min(mc_c + 1.0, u_mc_wholeHi);
  if (any(lessThan(mc_c, u_mc_brickLo)) || any(greaterThan(mc_c1, u_mc_brickHi)))
  {
    return -1.0e30;
  }
  vec3 mc_t = mc_p - mc_c;
  if (u_mc_nearest > 0.5)
  {
    mc_t = step(vec3(0.5), mc_t);  // nearest-neighbour interpolation: the nearest point, half-way rounding up
  }
  ivec3 mc_i = ivec3(mc_c - u_mc_brickLo);
  ivec3 mc_j = ivec3(mc_c1 - u_mc_brickLo);
  float mc_v000 = texelFetch(in_volume[0], mc_i, 0).r;
  float mc_v100 = texelFetch(in_volume[0], ivec3(mc_j.x, mc_i.y, mc_i.z), 0).r;
  float mc_v010 = texelFetch(in_volume[0], ivec3(mc_i.x, mc_j.y, mc_i.z), 0).r;
  float mc_v110 = texelFetch(in_volume[0], ivec3(mc_j.x, mc_j.y, mc_i.z), 0).r;
  float mc_v001 = texelFetch(in_volume[0], ivec3(mc_i.x, mc_i.y, mc_j.z), 0).r;
  float mc_v101 = texelFetch(in_volume[0], ivec3(mc_j.x, mc_i.y, mc_j.z), 0).r;
  float mc_v011 = texelFetch(in_volume[0], ivec3(mc_i.x, mc_j.y, mc_j.z), 0).r;
  float mc_v111 = texelFetch(in_volume[0], mc_j, 0).r;
  float mc_x00 = mix(mc_v000, mc_v100, mc_t.x);
  float mc_x10 = mix(mc_v010, mc_v110, mc_t.x);
  float mc_x01 = mix(mc_v001, mc_v101, mc_t.x);
  float mc_x11 = mix(mc_v011, mc_v111, mc_t.x);
  return mix(mix(mc_x00, mc_x10, mc_t.y), mix(mc_x01, mc_x11, mc_t.y), mc_t.z);
}

// mcNormalised from here on (the hook pieces' mcEndRay): the whole volume's normalisation
#define mcNormalised mcGlobalNormalised
