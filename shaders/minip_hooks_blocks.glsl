// mipcast piece: minip_hooks_blocks
// fills: Picking::Dec
// mode: augment
// Sampled MinIP's hooks (as minip_hooks) with block skipping, mirrored from
// mip_hooks_blocks: used when the transfer functions have a ceiling below
// the data maximum (a window below the tissue, as for airways). The running
// minimum starts at the ceiling and the ray stops at the floor (the float
// readout sets them to +/-1e30), and sampled_loop jumps over the samples in
// blocks whose minimum (in_mask, block minima with a margin of one point,
// mipcast/mappers/max_blocks.py) is not below it: a jumped sample cannot
// lower the running minimum. A ray still at the ceiling is drawn as the
// tables' top (normalised 1.0), one at or below the floor as their bottom
// (0.0), where the tables hold exactly the constant colours (amip_min_hooks).
// Missing values (filled above the data, u_mc_missingAbove; 1e30 when none):
// as mip_hooks_blocks, mirrored (a ray whose samples stay above the
// threshold met missing data only: mc_rayMissing, MC_MISSING_FLAG).
// MC_NO_SAMPLE_FLAG / mc_noSample: the ray has no sample (minip_hooks).
#define MC_SAMPLE_BLOCKS
#define MC_MISSING_FLAG
#define MC_NO_SAMPLE_FLAG
bool mc_noSample;
float mc_samplesFloor;
float mc_samplesCeiling;
float mc_samplesMissing;  // raw: the ray has met finite data once its minimum reaches it

void mcBeginRay(inout int first, inout int count)
{
  mc_samplesFloor = mcRaw(u_mc_skipFloor);
  mc_samplesCeiling = mcRaw(u_mc_skipCeiling);
  mc_samplesMissing = u_mc_missingAbove < 1.0e29 ? mcRaw(u_mc_missingAbove) : 3.4e38;
  mc_rayMax = 3.0e38;  // above every raw texel value (minip_hooks)
  mc_noSample = count <= first;
}

bool mcBlockSkips(float blockMin)
{
  return blockMin >= min(mc_rayMax, mc_samplesCeiling)
         && (mc_rayMax <= mc_samplesMissing || blockMin > mc_samplesMissing);
}

bool mcSample(float value, int i)
{
  mc_rayMax = min(mc_rayMax, value);
  return mc_rayMax > mc_samplesFloor;
}

void mcEndRay(int count)
{
  mc_rayMissing = mc_rayMax > mc_samplesMissing;
  mc_rayMax = MC_BOUNDED_NORMALISED(min(mc_rayMax, mc_samplesCeiling), mc_samplesFloor, mc_samplesCeiling);
}
