// mipcast piece: demip_two_pass_first_jitter
// fills: Base::Init
// mode: augment
// Two-pass DEMIP, pass 1, with jittering on: VTK reads its jitter pattern at
// gl_FragCoord, the pixel's position in pass 1's buffer (lower-left pixel of
// the viewport at 0). Pass 2 reads it at its own gl_FragCoord, which is the
// position in the window when it draws there directly. Read it again at pass
// 2's position (u_mc_pass2Offset: the viewport's offset in the window, or 0
// when pass 2 draws into a buffer of its own) and set the ray's start as VTK
// does, so that both passes take the same samples.
  jitterValue = texture2D(in_noiseSampler, (gl_FragCoord.xy + u_mc_pass2Offset)
                                           / vec2(textureSize(in_noiseSampler, 0))).x;
  g_rayJitter = g_dirStep * jitterValue;
  g_rayOrigin = ip_textureCoords.xyz + g_rayJitter;
