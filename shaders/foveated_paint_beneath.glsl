// mipcast piece: foveated_paint_beneath
// fills: Cropping::Exit
// mode: augment
// The masked levels of content-adaptive foveation are drawn over coarser
// levels (the deciding ones), which must not show through a ray this level
// casts: full quality draws that ray over what lay beneath the volume. So
// the ray is drawn over that picture here (B: the copy from before the
// frame's first level, u_mc_fovBeneath, foveated_mask_dec /
// foveated_coarse_dec) and the result blended with the level's weight w
// (foveated_weight has made g_fragColor w (c, a)): colour w (c + (1 - a) B),
// alpha w. A ray that draws nothing (mc_drawsNothing: clipped or cropped
// away, MC_DRAW_NOTHING in mip_globals, or missing data only,
// foveated_missing_flag) paints w B. A float readout (u_mc_fovPaintBeneath 0)
// paints nothing: such a ray draws nothing and keeps its miss. Once per
// ray, after the loop.
  if (u_mc_fovPaintBeneath < 0.5)
  {
    if (mc_drawsNothing)
    {
      discard;
    }
  }
  else
  {
    if (mc_drawsNothing)
    {
      g_fragColor = vec4(0.0);
    }
    vec2 mc_fovPaintAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    ivec2 mc_fovPaintPixel = clamp(ivec2(mc_fovPaintAt * u_mc_fovViewSize), ivec2(0), ivec2(u_mc_fovViewSize) - 1);
    vec3 mc_fovBeneath = texelFetch(u_mc_fovBeneath, mc_fovPaintPixel, 0).rgb;
    g_fragColor = vec4(g_fragColor.rgb + (mc_fovWeight - g_fragColor.a) * mc_fovBeneath, mc_fovWeight);
  }
