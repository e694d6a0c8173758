// mipcast piece: mip_hooks
// fills: Picking::Dec
// mode: augment
// Sampled MIP's hooks for sampled_loop: the largest sample along the ray.
void mcBeginRay(inout int first, inout int count)
{
  mc_rayMax = -1.0e30;
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
