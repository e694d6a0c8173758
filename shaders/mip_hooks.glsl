// mipcast piece: mip_hooks
// fills: Picking::Dec
// mode: augment
// Sampled MIP's hooks for sampled_loop: the largest sample along the ray.
// Raw texel values reach +-3.2e37 (mipcast.core.prepare.FLOAT_LIMITS, a
// missing value's fill included): the start lies below every one of them.
void mcBeginRay(inout int first, inout int count)
{
  mc_rayMax = -3.0e38;
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
