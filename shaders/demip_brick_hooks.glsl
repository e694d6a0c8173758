// mipcast piece: demip_brick_hooks
// fills: Picking::Dec
// mode: augment
// Distributed DEMIP, phase 2 on one brick, hooks for sampled_loop (with
// global_phase: the whole volume's sample positions and indices). The
// maximum is not this brick's but the whole ray's (mc_globalMax,
// demip_brick_fetch); the march stops at the first sample of the same
// material as that maximum, with DEMIP's test (demip_helpers: raw value >=
// min(max, ceiling) - band and above the floor's tolerance) loosened by
// MC_BRICK_SLACK of the window: the maximum reached this brick through a
// float readout in data units, so the maximum's own sample must still
// match (the floor test on the maximum is DEMIP's, unloosened). mc_matchIndex is that sample's WHOLE-ray index (-1: none in this
// brick); the ranks' minimum is the whole ray's first same-material sample.
// No DEMIP term (no march) where the maximum is not above the floor. The
// maximum (mc_globalMax) and the material window's ends (u_mc_brickWindow:
// floor, ceiling, eps, floor tolerance) come in this brick's normalised
// scalar, the ends those of the transfer functions over the WHOLE volume's
// range (a brick's own range would clamp them).
#define MC_BRICK_SLACK 1.0e-6

float mc_globalMax;   // normalised (this brick's); > 1e29: no maximum
float mc_brickAbove;  // the raw same-material threshold

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
  float mc_floorRaw = mcRaw(u_mc_brickWindow.x);
  float mc_ceilingRaw = mcRaw(u_mc_brickWindow.y);
  float mc_span = mc_ceilingRaw - mc_floorRaw;
  mc_window = vec4(mc_floorRaw, mc_ceilingRaw, u_mc_brickWindow.z * mc_span,
                   mc_floorRaw + u_mc_brickWindow.w * mc_span);
  float mc_maxRaw = mcRaw(mc_globalMax);
  float mc_width = mc_window.y - mc_window.x;
  mc_brickAbove = min(mc_maxRaw, mc_window.y) - mc_window.z - MC_BRICK_SLACK * abs(mc_width);
  if (!(mc_globalMax < 1.0e29) || !(mc_maxRaw > mc_window.w))
  {
    count = first;  // no DEMIP term on this ray: march nothing
  }
}

bool mcSample(float value, int i)
{
  if (value >= mc_brickAbove && value > mc_window.w)
  {
    mc_matchIndex = i;
    return false;
  }
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mc_globalMax;
}
