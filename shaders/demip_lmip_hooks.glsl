// mipcast piece: demip_lmip_hooks
// fills: Picking::Dec
// mode: augment
// Local MIP (Sato et al.) with DEMIP, hooks for sampled_loop: as
// demip_hooks, but the ray ends before the first sample that falls below a
// running maximum above u_mc_localThreshold (normalised). The maximum is
// then the first local maximum above the threshold (the global maximum if
// no sample exceeds it), and the same-material search runs on that
// shortened ray.
#define MC_SECOND_MARCH

float mc_localRaw;

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
  mc_localRaw = mcRaw(u_mc_localThreshold);
}

bool mcSample(float value, int i)
{
  if (value < mc_rayMax && mc_rayMax > mc_localRaw)
  {
    return false;
  }
  mcDemipSample(value, i);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_rayMax);
}
