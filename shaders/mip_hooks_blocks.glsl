// mipcast piece: mip_hooks_blocks
// fills: Picking::Dec
// mode: augment
// Sampled MIP's hooks (as mip_hooks) with block skipping, used when the
// transfer functions have a floor above the data minimum (a window above
// the background). The running maximum starts at the floor and the ray
// stops at the ceiling (the float readout sets them to -/+1e30), and
// sampled_loop jumps over the samples in blocks that cannot raise it
// (MC_SAMPLE_BLOCKS; mcBlockSkips says which blocks cannot). The
// block maxima (in_mask, mipcast/mappers/max_blocks.py, margin 1: a block
// bounds every sample within one point of its cells, so rounding in the
// sample's position or in the texture unit's choice of cell never lets a
// jumped sample escape) make the jumps exact: a jumped sample is not above
// the running maximum. A ray still at the floor is drawn as the tables'
// bottom (normalised 0.0), one at or above the ceiling as their top (1.0),
// where the tables hold exactly the constant colours (amip_max_hooks).
// Missing values (filled below the data, u_mc_missingBelow; -1e30 when none):
// mc_rayMax is the samples' own maximum and the floor bounds it where it is
// used, so a ray whose samples stay below the missing threshold met missing
// data only (mc_rayMissing, MC_MISSING_FLAG: missing_exit and
// foveated_missing_flag draw nothing), whatever the opacity at the floor;
// until the ray has met finite data only blocks of missing data (maximum
// below the threshold) are jumped. Per sample the work is the plain hooks'.
#define MC_SAMPLE_BLOCKS
#define MC_MISSING_FLAG
float mc_samplesFloor;
float mc_samplesCeiling;
float mc_samplesMissing;  // raw: the ray has met finite data once its maximum reaches it

void mcBeginRay(inout int first, inout int count)
{
  mc_samplesFloor = mcRaw(u_mc_skipFloor);
  mc_samplesCeiling = mcRaw(u_mc_skipCeiling);
  mc_samplesMissing = u_mc_missingBelow > -1.0e29 ? mcRaw(u_mc_missingBelow) : -3.4e38;
  mc_rayMax = -3.0e38;  // below every raw texel value (mip_hooks)
}

bool mcBlockSkips(float blockMax)
{
  return blockMax <= max(mc_rayMax, mc_samplesFloor)
         && (mc_rayMax >= mc_samplesMissing || blockMax < mc_samplesMissing);
}

bool mcSample(float value, int i)
{
  mc_rayMax = max(mc_rayMax, value);
  return mc_rayMax < mc_samplesCeiling;
}

void mcEndRay(int count)
{
  mc_rayMissing = mc_rayMax < mc_samplesMissing;
  mc_rayMax = MC_BOUNDED_NORMALISED(max(mc_rayMax, mc_samplesFloor), mc_samplesFloor, mc_samplesCeiling);
}
