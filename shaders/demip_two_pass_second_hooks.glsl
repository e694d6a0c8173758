// mipcast piece: demip_two_pass_second_hooks
// fills: Picking::Dec
// mode: augment
// Two-pass DEMIP, pass 2, hooks for sampled_loop: the first march is the one
// sample pass 1 named as the maximum (mc_firstMax, demip_two_pass_fetch),
// then DEMIP's second march (demip_helpers) from pass 1's start index; it
// ends at the maximum's own sample at the latest. Same samples and same
// tests as the one-pass demip_hooks, so the same mc_rayMax, mc_matchIndex,
// mc_depth.
#define MC_SECOND_MARCH

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
  mc_start = mc_firstStart;
  first = mc_firstMax;
  count = mc_firstMax + 1;
}

bool mcSample(float value, int i)
{
  mc_rayMax = max(mc_rayMax, value);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_rayMax);
}
