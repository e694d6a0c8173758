// mipcast piece: demip_hooks_blocks
// fills: Picking::Dec
// mode: augment
// Depth-enhanced MIP's hooks (as demip_hooks) with block skipping, used when
// the transfer functions have a floor above the data minimum. March 1 starts
// its running maximum at the floor (u_mc_skipFloor), jumps over blocks whose
// maximum is not above it (MC_SAMPLE_BLOCKS, block maxima as mip_hooks_blocks)
// and ends one sample after the maximum reaches the ceiling (u_mc_skipCeiling);
// the float readout sets them to -/+1e30. Exact, picture and depth:
// - a jumped sample is not above the running maximum, so its level is not
//   above the running level and demip_helpers' bookkeeping would not have
//   changed at it;
// - the first same-material sample is never jumped: a jump at a block whose
//   maximum is at least that sample's value would need an earlier read
//   sample at least as high (itself of the same material), or the floor
//   start, below the material's low end;
// - after the ceiling the level cannot rise (levels saturate at the ceiling),
//   and the sample that reached it stays in march 2's range.
// A ray still at the floor is drawn as the tables' bottom (normalised 0.0),
// one at or above the ceiling as their top (1.0), as mip_hooks_blocks does.
// mc_rayMax is the samples' own maximum (demip_helpers), the floor bounding
// it where it is used, as in mip_hooks_blocks, whose missing-value rule
// this follows (mc_rayMissing, MC_MISSING_FLAG).
#define MC_SECOND_MARCH
#define MC_SAMPLE_BLOCKS
#define MC_MISSING_FLAG
float mc_samplesFloor;
float mc_samplesCeiling;
float mc_samplesMissing;  // raw: the ray has met finite data once its maximum reaches it

void mcBeginRay(inout int first, inout int count)
{
  mcDemipBeginRay();
  mc_samplesFloor = mcRaw(u_mc_skipFloor);
  mc_samplesCeiling = mcRaw(u_mc_skipCeiling);
  mc_samplesMissing = u_mc_missingBelow > -1.0e29 ? mcRaw(u_mc_missingBelow) : -3.4e38;
}

bool mcBlockSkips(float blockMax)
{
  return blockMax <= max(mc_rayMax, mc_samplesFloor)
         && (mc_rayMax >= mc_samplesMissing || blockMax < mc_samplesMissing);
}

bool mcSample(float value, int i)
{
  if (mc_rayMax >= mc_samplesCeiling)
  {
    return false;  // the sample before reached the ceiling: the ray ends after it
  }
  mcDemipSample(value, i);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMissing = mc_rayMax < mc_samplesMissing;
  mc_rayMax = MC_BOUNDED_NORMALISED(max(mc_rayMax, mc_samplesFloor), mc_samplesFloor, mc_samplesCeiling);
}
