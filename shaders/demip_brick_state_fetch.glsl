// mipcast piece: demip_brick_state_fetch
// fills: Terminate::Init
// mode: replace
// MIDA drawn in bricks (demip_brick_mida_hooks): as demip_brick_fetch, but
// the float texture shared as in_depthSampler holds two numbers per pixel,
// the state of the compositing left by the bricks in front (red: the running
// maximum of the material, green: the accumulated opacity), read into
// mc_brickState. Also does the refusal piece's job; ray set-up as
// mcSetRayEnd (mip_globals), ending at the scene depth in alpha as
// demip_brick_fetch's.
  mcRefuseIfAsked();
  vec2 mc_at = gl_FragCoord.xy * in_inverseWindowSize;
  mc_brickState = texture2D(in_depthSampler, mc_at);
  mcSetSceneRayEnd(mc_at, mc_brickState.a);
#ifdef MC_WHOLE_RAY_END
  mcWholeRayEnd();
#endif
