// mipcast piece: mip_sampled_loop
// fills: Shading::Init
// mode: replace
// Sampled MIP with a counted loop. Samples sit where VTK's stock loop puts
// them: the first one step after the box entry (g_dataPos), then every
// g_dirStep while the position stays inside the point bounds and before the
// depth-buffer / clipping termination (g_terminatePointMax). Sample i is at
// g_dataPos + i * g_dirStep, not a running sum: summing thousands of float
// steps (dense sampling) drifts by a good fraction of a voxel.
  vec3 mc_step = g_dirStep;
  vec3 mc_limit = mix(in_texMin[0], in_texMax[0], vec3(greaterThan(mc_step, vec3(0.0))));
  vec3 mc_toExit = (mc_limit - g_dataPos) / mc_step;
  mc_toExit = mix(mc_toExit, vec3(1.0e30), vec3(equal(mc_step, vec3(0.0))));
  float mc_stepsInBox = min(min(mc_toExit.x, mc_toExit.y), mc_toExit.z);
  int mc_count = 1 + int(max(0.0, floor(mc_stepsInBox)));
  mc_count = min(mc_count, int(ceil(max(g_terminatePointMax, 0.0))) + 1);
  mc_rayMax = -1.0e30;
  for (int mc_i = 0; mc_i < mc_count; ++mc_i)
  {
    float mc_value = texture3D(in_volume[0], g_dataPos + float(mc_i) * mc_step).r;
    mc_rayMax = max(mc_rayMax, mc_value);
  }
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  g_exit = true;
