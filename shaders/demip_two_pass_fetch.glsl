// mipcast piece: demip_two_pass_fetch
// fills: Terminate::Init
// mode: replace
// Two-pass DEMIP, pass 2: read what pass 1 stored for this pixel. VTK's own
// code at this tag reads in_depthSampler as the scene's depth (to end rays
// at opaque geometry); here in_depthSampler is pass 1's float image, shared
// by the mapper, so that code is replaced. Pass 1 already ended its rays at
// opaque geometry and cast none where geometry hides the volume; pass 2
// needs no scene depth (its march stops at the maximum's sample).
// Pass 1's image starts at the viewport's lower-left pixel; so does pass 2's
// reduced-resolution or render-to-image buffer (u_mc_toImage = 1), where
// VTK's window uniforms may still carry the viewport's offset in the window.
// Also does the refusal piece's job (this tag takes one piece).
  mcRefuseIfAsked();
  vec2 mc_at = (gl_FragCoord.xy - (1.0 - u_mc_toImage) * in_windowLowerLeftCorner) * in_inverseWindowSize;
  float mc_code = texture2D(in_depthSampler, mc_at).r;
  if (mc_code > 0.5 && mc_code < 1.5)
  {
    discard;  // pass 1 cast no ray here
  }
  if (mc_code < 0.0)
  {
    int mc_packedCode = int(-1.0 - mc_code);
    mc_firstStart = mc_packedCode / u_mc_indexBase;
    mc_firstMax = mc_packedCode - mc_firstStart * u_mc_indexBase;
  }
  else
  {
    mc_firstStart = 0;
    mc_firstMax = int(mc_code - 2.0);
  }
  // VTK's bookkeeping (mcSetRayEnd, mip_globals), with the ray ending at the far plane (NDC z = 1):
  // clipping planes (Clipping::Init) move the ray's start exactly as in pass 1.
  mcSetRayEnd(mc_at, 1.0);
