// mipcast piece: demip_brick_mida_hooks
// fills: Picking::Dec
// mode: augment
// MIDA (demip_mida_hooks) drawn in bricks, one brick's part
// (mipcast/mappers/demip_ordered_bricks.py), hooks for sampled_loop with
// global_phase (the whole volume's sample positions). The bricks are drawn
// front to back; each continues the compositing from the state the bricks
// in front left (demip_brick_state_fetch: the running maximum of the
// material and the accumulated opacity A). The colour C enters MIDA's
// update linearly (C' = beta C + (1 - beta A) a c, where beta and A do not
// depend on C), so the brick starts its colour at 0 and also reads out the
// product P of its betas: the colour after it is P C_in + C_brick (the CPU
// applies it). The readout (demip_brick_mida_readout, u_mc_brickChannel)
// gives C_brick (channels 0, 1, 2), A (3), P (4) and the running material
// (5). The material window (u_mc_brickWindow: floor, ceiling) is the
// transfer functions' over the WHOLE volume's range, in this brick's
// normalised scalar.
vec4 mc_brickState;
float mc_runMaterial;
float mc_betaProduct;
vec4 mc_sum;

void mcBeginRay(inout int first, inout int count)
{
  mc_floorRaw = mcRaw(u_mc_brickWindow.x);
  mc_toMaterial = 1.0 / (mcRaw(u_mc_brickWindow.y) - mc_floorRaw);
  mc_runMaterial = mc_brickState.r;
  mc_sum = vec4(0.0, 0.0, 0.0, mc_brickState.g);
  mc_betaProduct = 1.0;
}

bool mcSample(float value, int i)
{
  float s = mcNormalised(value);
  float alpha = computeOpacity(MC_OPACITY_AT(s));  // (mip_globals)
  mc_betaProduct *= mcMidaStep(mcMaterial(value), alpha, computeColor(MC_COLOR_AT(s), alpha).rgb, mc_runMaterial, mc_sum);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = 0.0;
}
