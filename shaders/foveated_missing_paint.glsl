// mipcast piece: foveated_missing_paint
// fills: Cropping::Exit
// mode: augment
// missing_exit for the masked levels of content-adaptive foveation: coarser
// levels were drawn beneath this one, so a cast ray whose value is below
// the finite minimum (it saw no finite data) must not draw nothing -- the
// coarse levels' stretched picture would show through where full quality
// shows what lies behind the volume. It paints that picture (the copy from
// before the frame's first level, foveated_mask_dec / foveated_coarse_dec)
// with the level's blend weight (foveated_weight: mc_fovWeight), as a ray
// of the background would. A float readout (u_mc_fovPaintMiss 0) keeps the
// miss: the ray draws nothing. Once per ray, after the loop.
  if (mc_rayMax < u_mc_missingBelow)
  {
    if (u_mc_fovPaintMiss < 0.5)
    {
      discard;
    }
    vec2 mc_fovMissAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    ivec2 mc_fovMissPixel = clamp(ivec2(mc_fovMissAt * u_mc_fovViewSize), ivec2(0), ivec2(u_mc_fovViewSize) - 1);
    g_fragColor = vec4(texelFetch(u_mc_fovBeneath, mc_fovMissPixel, 0).rgb, 1.0) * mc_fovWeight;
  }
