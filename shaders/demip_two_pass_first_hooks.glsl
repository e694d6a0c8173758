// mipcast piece: demip_two_pass_first_hooks
// fills: Picking::Dec
// mode: augment
// Two-pass DEMIP, pass 1, hooks for sampled_loop: DEMIP's first march (same
// samples, same level bookkeeping: mcDemipSample) that also remembers the
// index of the first maximum sample. No second march here:
// demip_two_pass_store writes both indices to the float image for pass 2.
int mc_maxAt;

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
  mc_maxAt = 0;
}

bool mcSample(float value, int i)
{
  mc_maxAt = value > mc_rayMax ? i : mc_maxAt;
  mcDemipSample(value, i);
  return true;
}

void mcEndRay(int count)
{
  mc_firstPacked = count <= u_mc_indexBase;
  mc_firstStart = mc_firstPacked ? mc_start : 0;
  mc_firstMax = mc_maxAt;
  mc_rayMax = mcNormalised(mc_rayMax);
}
