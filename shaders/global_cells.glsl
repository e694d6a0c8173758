// mipcast piece: global_cells
// fills: Termination::Dec
// mode: augment
// One brick of a distributed volume (mipcast.distributed) for the exact
// projections' cell walk (amip_cell): each pixel's ray is cast in the WHOLE
// volume's absolute point-index space from uniforms that are the same on
// every rank (mipcast.distributed.ray_uniforms, as the global_phase piece
// of the sampled loop), t = 0 at the whole box's entry; the brick walks its
// own cells (whole indices, corners fetched at cell - u_mc_brickLo) from
// where the ray enters its box (or VTK's near-plane cap, the camera inside
// the volume) to where it leaves, and every voxel plane's
// ray parameter is computed from the plane's index, (plane - origin) / dir,
// never accumulated, so a cell's segment (and its cubic) is the same bit
// for bit on every rank whatever the split. mcGlobalNormalised: VTK's
// normalisation with the WHOLE volume's range (u_mc_globalNorm, as in
// global_phase).
#define MC_GLOBAL_CELLS

float mcGlobalNormalised(float raw)
{
  if (u_mc_globalNorm.x > 1.5)
  {
    return mcNormalised(raw) * u_mc_globalNorm.y + u_mc_globalNorm.z;
  }
  return u_mc_globalNorm.x > 0.5 ? raw * u_mc_globalNorm.y + u_mc_globalNorm.z : mcNormalised(raw);
}

// Its inverse: a value on the whole volume's scale (the missing threshold, u_mc_missingBelow/Above) as
// this brick's raw texel value, which the cell hooks compare with the corners (MC_CELLS_RAW).
float mcGlobalRaw(float normalised)
{
  float local = (normalised - u_mc_globalNorm.z) / u_mc_globalNorm.y;
  if (u_mc_globalNorm.x > 1.5)
  {
    return mcRaw(local);
  }
  return u_mc_globalNorm.x > 0.5 ? local : mcRaw(normalised);
}
#define MC_CELLS_RAW mcGlobalRaw

// The whole volume's ray: entry point (absolute point index), direction
// (point-index units per unit world length) and where the walk starts (ray
// parameter from the entry: 0, or where the camera is inside the volume the
// near-plane cap VTK starts the ray at when it lies beyond the entry:
// u_mc_rayCap, as in global_phase); false when it misses the box or leaves
// it before the cap.
bool mcGlobalRay(out vec3 entry, out vec3 dir, out float start)
{
  vec2 ndc = 2.0 * gl_FragCoord.xy * in_inverseWindowSize - 1.0;
  vec3 point = u_mc_rayPoint0 + ndc.x * u_mc_rayPointX + ndc.y * u_mc_rayPointY;
  vec3 toward = mix(u_mc_rayDirection, point - u_mc_rayEye.xyz, u_mc_rayEye.w);
  dir = toward / length(toward * u_mc_raySpacing);
  vec2 whole = mcLineThroughBox(point, dir, u_mc_wholeLo, u_mc_wholeHi);
  float sIn = whole.x;
  float sOut = whole.y;
  entry = point + sIn * dir;
  float capAlong = dot(u_mc_rayCap.xyz, dir);
  start = capAlong > 0.0 ? max((u_mc_rayCap.w - dot(u_mc_rayCap.xyz, point)) / capAlong - sIn, 0.0) : 0.0;
  return sIn + start <= sOut;
}

// mcNormalised from here on (the cell hooks' mcCellsEnd): the whole volume's normalisation
#define mcNormalised mcGlobalNormalised
