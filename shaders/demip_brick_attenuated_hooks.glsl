// mipcast piece: demip_brick_attenuated_hooks
// fills: Picking::Dec
// mode: augment
// Attenuated MIP (demip_attenuated_hooks) drawn in bricks, one brick's part
// (mipcast/mappers/demip_ordered_bricks.py), hooks for sampled_loop with
// global_phase (the whole volume's sample positions). The bricks are drawn
// front to back; each continues the sum of the material crossed in front of
// it (mc_globalMax, read by demip_brick_fetch from the float texture; > 1e29:
// none yet, 0), so every sample's attenuation exp(-decay * crossed) is the
// single texture's, and reads out its best attenuated material (channel 0)
// and the crossed sum after it (channel 1, u_mc_brickChannel;
// demip_brick_attenuated_readout): the CPU's maximum over the bricks' best
// is the whole ray's. The material window (u_mc_brickWindow: floor,
// ceiling) is the transfer functions' over the WHOLE volume's range, in
// this brick's normalised scalar.
float mc_globalMax;
float mc_decay;
float mc_crossed;
float mc_best;

void mcBeginRay(inout int first, inout int count)
{
  mc_floorRaw = mcRaw(u_mc_brickWindow.x);
  mc_toMaterial = 1.0 / (mcRaw(u_mc_brickWindow.y) - mc_floorRaw);
  vec3 spacing = abs(in_cellSpacing[0]);
  mc_decay = u_mc_attenuation * in_sampleDistance / min(min(spacing.x, spacing.y), spacing.z);
  mc_crossed = mc_globalMax < 1.0e29 ? mc_globalMax : 0.0;
  mc_best = -1.0;  // no sample in this brick
}

bool mcSample(float value, int i)
{
  float material = mcMaterial(value);
  mc_best = max(mc_best, material * exp(-mc_decay * mc_crossed));
  mc_crossed += material;
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mc_best;
}
