// mipcast piece: demip_two_pass_second
// fills: Shading::Init
// mode: replace
// Two-pass DEMIP, pass 2: the maximum is the sample pass 1 named (one
// fetch), then demip_loop's second march from pass 1's start index; it ends
// at the maximum's own sample at the latest. Same samples and same tests as
// the one-pass demip_loop, so the same mc_rayMax, mc_matchIndex, mc_depth.
  vec4 mc_window = mcMaterialWindow();
  mc_rayMax = texture3D(in_volume[0], g_dataPos + float(mc_firstMax) * g_dirStep).r;
  mc_matchIndex = -1;
  if (mc_rayMax > mc_window.w && u_mc_needDepth > 0.5)
  {
    mcFindSameMaterial(mc_firstStart, mc_firstMax + 1, mc_rayMax, mc_window);
  }
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  g_exit = true;
