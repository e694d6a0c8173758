// mipcast piece: demip_loop
// fills: Shading::Init
// mode: replace
// Depth-enhanced MIP, both marches in one shader, on the samples of
// mip_sampled_loop (mcSampleCount; sample k at g_dataPos + k * g_dirStep).
//
// The material of a raw value v is its place in the transfer functions'
// window, clamp((v - floor) / (ceiling - floor), 0, 1) (u_mc_floor and
// u_mc_ceiling, normalised). It is monotone, so "within eps of the maximum's
// material, and above the floor" is the raw test
//   v >= min(max, ceiling) - band  &&  v > low
// (mcMaterialWindow; a background exactly at the floor stays background).
//
// March 1 takes the maximum and follows the level of the running maximum,
// floor((min(v, ceiling) - low) / band) (monotone in v), remembering where
// it first reached the level below its current one. Every earlier sample
// lies more than one band below the final maximum and cannot match (nor can
// samples at or below low), so march 2 (mcFindSameMaterial) starts there:
// the result equals a march from the ray start. Levels are at least 1e-6 of
// the window wide, so that they stay distinct in float32 for tiny eps.
// March 2 is skipped when nothing uses the depth (u_mc_needDepth = 0).
  int mc_count = mcSampleCount();
  vec4 mc_window = mcMaterialWindow();
  float mc_perLevel = 1.0 / max(mc_window.z, 1.0e-6 * (mc_window.y - mc_window.x));
  float mc_levelBias = -mc_window.w * mc_perLevel;
  float mc_level = -1.0e30;  // level of the running maximum
  int mc_entered = 0;        // where the running maximum entered mc_level
  int mc_start = 0;          // where it first reached mc_level - 1 or above
  mc_rayMax = -1.0e30;
  mc_matchIndex = -1;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * g_dirStep).r;
    mc_rayMax = max(mc_rayMax, mc_value);
    mcTrackLevel(floor(min(mc_value, mc_window.y) * mc_perLevel + mc_levelBias), mc_i,
                 mc_level, mc_entered, mc_start);
  }
  if (mc_rayMax > mc_window.w && u_mc_needDepth > 0.5)
  {
    mcFindSameMaterial(mc_start, mc_count, mc_rayMax, mc_window);
  }
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  g_exit = true;
