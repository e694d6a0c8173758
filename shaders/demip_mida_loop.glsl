// mipcast piece: demip_mida_loop
// fills: Shading::Init
// mode: replace
// MIDA, maximum intensity difference accumulation (Bruckner and Groeller
// 2009), pure form (gamma = 0): front-to-back compositing of the transfer
// functions' colour c_k and opacity a_k, where a sample that raises the
// running maximum of the material (place in the window, 0..1) by delta_k
// first fades what is in front of it by beta_k = 1 - delta_k:
//   C = beta C + (1 - beta A) a_k c_k,   A = beta A + (1 - beta A) a_k.
// The result (premultiplied) goes to mc_composite for demip_mida_color;
// mc_rayMax keeps the sampled maximum for the float readout. No DEMIP term.
// Same samples as mip_sampled_loop (mcSampleCount).
  int mc_count = mcSampleCount();
  float mc_floorRaw = mcDemipRaw(u_mc_floor);
  float mc_toMaterial = 1.0 / (mcDemipRaw(u_mc_ceiling) - mc_floorRaw);
  float mc_runMaterial = 0.0;
  vec4 mc_sum = vec4(0.0);
  mc_rayMax = -1.0e30;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * g_dirStep).r;
    mc_rayMax = max(mc_rayMax, mc_value);
    float mc_material = clamp((mc_value - mc_floorRaw) * mc_toMaterial, 0.0, 1.0);
    float mc_beta = 1.0 - max(mc_material - mc_runMaterial, 0.0);
    mc_runMaterial = max(mc_runMaterial, mc_material);
    vec4 mc_scalar = vec4(mc_value * in_volume_scale[0].r + in_volume_bias[0].r);
    float mc_alpha = computeOpacity(mc_scalar);
    vec3 mc_color = computeColor(mc_scalar, mc_alpha).rgb;
    float mc_fresh = (1.0 - mc_beta * mc_sum.a) * mc_alpha;
    mc_sum = vec4(mc_beta * mc_sum.rgb + mc_fresh * mc_color, mc_beta * mc_sum.a + mc_fresh);
  }
  mc_composite = mc_sum;
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  mc_matchIndex = -1;
  g_exit = true;
