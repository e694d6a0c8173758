// mipcast piece: minip_hooks
// fills: Picking::Dec
// mode: augment
// Sampled MinIP's hooks for sampled_loop: the smallest sample along the ray,
// as VTK's MINIMUM_INTENSITY blend takes it (the first sample sets it; a ray
// with no sample keeps stock's start value, normalised 1).
// MC_NO_SAMPLE_FLAG / mc_noSample: whether the ray took no sample (read by
// depth_composite_min, which draws nothing then).
#define MC_NO_SAMPLE_FLAG
bool mc_noSample;

void mcBeginRay(inout int first, inout int count)
{
  mc_rayMax = 3.0e38;  // above every raw texel value (+-3.2e37 at most: mip_hooks)
}

bool mcSample(float value, int i)
{
  mc_rayMax = min(mc_rayMax, value);
  return true;
}

void mcEndRay(int count)
{
  mc_noSample = mc_rayMax > 1.0e38;
#ifdef MC_GLOBAL_PHASE
  // a brick holding none of the ray's samples has no value (mipcast.mappers.bricked_draw)
  mc_rayMax = mc_noSample ? 1.0e30 : mcNormalised(mc_rayMax);
#else
  mc_rayMax = count > 0 ? mcNormalised(mc_rayMax) : 1.0;
#endif
}
