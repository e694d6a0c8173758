// mipcast piece: demip_hooks
// fills: Picking::Dec
// mode: augment
// Depth-enhanced MIP's hooks for sampled_loop: both marches in one shader
// (march 1: mcDemipBeginRay / mcDemipSample, march 2: the second-march hooks;
// all in demip_helpers, which explains the level bookkeeping).
#define MC_SECOND_MARCH

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
}

bool mcSample(float value, int i)
{
  mcDemipSample(value, i);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_rayMax);
}
