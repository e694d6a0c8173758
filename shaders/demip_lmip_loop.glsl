// mipcast piece: demip_lmip_loop
// fills: Shading::Init
// mode: replace
// Local MIP (Sato et al.) with DEMIP: as demip_loop, but the ray ends
// before the first sample that falls below a running maximum above
// u_mc_localThreshold (normalised). The maximum is then the first local
// maximum above the threshold (the global maximum if no sample exceeds
// it), and the same-material search runs on that shortened ray.
  int mc_count = mcSampleCount();
  vec4 mc_window = mcMaterialWindow();
  float mc_localRaw = mcDemipRaw(u_mc_localThreshold);
  float mc_perLevel = 1.0 / max(mc_window.z, 1.0e-6 * (mc_window.y - mc_window.x));
  float mc_levelBias = -mc_window.w * mc_perLevel;
  float mc_level = -1.0e30;
  int mc_entered = 0;
  int mc_start = 0;
  mc_rayMax = -1.0e30;
  mc_matchIndex = -1;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * g_dirStep).r;
    if (mc_value < mc_rayMax && mc_rayMax > mc_localRaw)
    {
      mc_count = mc_i;
      break;
    }
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
