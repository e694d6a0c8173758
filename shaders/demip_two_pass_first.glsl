// mipcast piece: demip_two_pass_first
// fills: Shading::Init
// mode: replace
// Two-pass DEMIP, pass 1: the MIP march of demip_loop (same samples, same
// level bookkeeping through mcTrackLevel) that also remembers the index of
// the first maximum sample. No second march here: demip_two_pass_store
// writes both indices to the float image for pass 2.
  int mc_count = mcSampleCount();
  vec4 mc_window = mcMaterialWindow();
  float mc_perLevel = 1.0 / max(mc_window.z, 1.0e-6 * (mc_window.y - mc_window.x));
  float mc_levelBias = -mc_window.w * mc_perLevel;
  float mc_level = -1.0e30;
  int mc_entered = 0;
  int mc_start = 0;
  int mc_maxAt = 0;
  mc_rayMax = -1.0e30;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * g_dirStep).r;
    mc_maxAt = mc_value > mc_rayMax ? mc_i : mc_maxAt;
    mc_rayMax = max(mc_rayMax, mc_value);
    mcTrackLevel(floor(min(mc_value, mc_window.y) * mc_perLevel + mc_levelBias), mc_i,
                 mc_level, mc_entered, mc_start);
  }
  mc_firstPacked = mc_count <= u_mc_indexBase;
  mc_firstStart = mc_firstPacked ? mc_start : 0;
  mc_firstMax = mc_maxAt;
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  g_exit = true;
