// mipcast piece: foveated_brick_color
// fills: Shading::Exit
// mode: replace
// The colour of a foveated DEMIP level composited over bricks
// (foveated_brick_hooks' u_mc_fovColours): the premultiplied colour the CPU composite
// gave this ray, read from the level's colour texture at the same texel as
// its value. foveated_weight then scales it by the level's blend weight,
// exactly as it scales the colour demip_color writes for one texture.
  g_fragColor = texture2D(u_mc_fovColours,
                          (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize);
  g_srcColor = g_fragColor;
