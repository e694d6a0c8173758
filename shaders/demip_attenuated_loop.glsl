// mipcast piece: demip_attenuated_loop
// fills: Shading::Init
// mode: replace
// Attenuated MIP in the style of napari (vispy's attenuated_mip): the largest
// material m_k (place in the window, 0..1) after attenuation by the
// material already crossed in front of it,
//   best = max_k m_k * exp(-u_mc_attenuation * h * sum_{j<k} m_j),
// h the sample distance in voxels (smallest spacing), so the attenuation is
// per voxel of full material and independent of the sample distance. The
// ray's value is the scalar with that material (floor + best * window); no
// DEMIP term. Same samples as mip_sampled_loop (mcSampleCount).
  int mc_count = mcSampleCount();
  float mc_floorRaw = mcDemipRaw(u_mc_floor);
  float mc_toMaterial = 1.0 / (mcDemipRaw(u_mc_ceiling) - mc_floorRaw);
  vec3 mc_spacing = abs(in_cellSpacing[0]);
  float mc_decay = u_mc_attenuation * in_sampleDistance / min(min(mc_spacing.x, mc_spacing.y), mc_spacing.z);
  float mc_crossed = 0.0;
  float mc_best = 0.0;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * g_dirStep).r;
    float mc_material = clamp((mc_value - mc_floorRaw) * mc_toMaterial, 0.0, 1.0);
    mc_best = max(mc_best, mc_material * exp(-mc_decay * mc_crossed));
    mc_crossed += mc_material;
  }
  mc_rayMax = u_mc_floor + mc_best * (u_mc_ceiling - u_mc_floor);
  mc_matchIndex = -1;
  g_exit = true;
