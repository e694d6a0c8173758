// mipcast piece: demip_mida_hooks
// fills: Picking::Dec
// mode: augment
// MIDA, maximum intensity difference accumulation (Bruckner and Groeller
// 2009), pure form (gamma = 0), hooks for sampled_loop: front-to-back
// compositing of the transfer functions' colour c_k and opacity a_k, where a
// sample that raises the running maximum of the material (place in the
// window, 0..1, mcMaterial) by delta_k first fades what is in front of it by
// beta_k = 1 - delta_k:
//   C = beta C + (1 - beta A) a_k c_k,   A = beta A + (1 - beta A) a_k.
// The result (premultiplied) goes to mc_composite for demip_mida_color;
// mc_rayMax keeps the sampled maximum for the float readout. No DEMIP term.
float mc_runMaterial;
vec4 mc_sum;

void mcBeginRay(inout int first, inout int count)
{
  mcBeginMaterial();
  mc_runMaterial = 0.0;
  mc_sum = vec4(0.0);
  mc_rayMax = -3.0e38;  // below every raw texel value (mip_hooks)
}

bool mcSample(float value, int i)
{
  mc_rayMax = max(mc_rayMax, value);
  float s = mcNormalised(value);
  float alpha = computeOpacity(MC_OPACITY_AT(s));  // (mip_globals)
  mcMidaStep(mcMaterial(value), alpha, computeColor(MC_COLOR_AT(s), alpha).rgb, mc_runMaterial, mc_sum);
  return true;
}

void mcEndRay(int count)
{
  mc_composite = mc_sum;
  mc_rayMax = mcNormalised(mc_rayMax);
  mc_matchIndex = -1;
}
