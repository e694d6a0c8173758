// mipcast piece: demip_color
// fills: Shading::Exit
// mode: replace
// Colour: the maximum through the transfer functions exactly as MIP does;
// where DEMIP found a same-material sample (maximum above the floor), the
// straight (not premultiplied) colour becomes
//   c = c_MIP * (1 - d_w) + 2 d_w (1 - depth)           (Eq. 1)
//   c = c * (1 - sph_w) + c_sphere * sph_w               (Eq. 2)
//   c = c * (1 - chroma_w) + c_chroma(depth) * chroma_w  (pseudo-chromadepth)
// clamped to [0, 1]; the opacity stays MIP's, then alpha is premultiplied.
  g_srcColor = computeColor(MC_COLOR_AT(mc_rayMax), computeOpacity(MC_OPACITY_AT(mc_rayMax)));  // (mip_globals)
  if (mc_matchIndex >= 0)
  {
    vec3 mc_color = g_srcColor.rgb * (1.0 - u_mc_depthWeight) + 2.0 * u_mc_depthWeight * (1.0 - mc_depth);
    if (u_mc_sphereWeight > 0.0)
    {
      mc_color = mix(mc_color, mcSphereColor(mc_hitTex), u_mc_sphereWeight);
    }
    mc_color = mix(mc_color, mcChromaColor(mc_depth), u_mc_chromaWeight);
    g_srcColor.rgb = clamp(mc_color, 0.0, 1.0);
  }
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
