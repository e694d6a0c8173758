// mipcast piece: depth_composite_min
// fills: DepthPass::Exit
// mode: augment
// depth_composite for the minimum projections (MinIP, analytic MinIP): the
// fragment's depth increases with the ray's value (u_mc_depthScale,
// u_mc_depthBias map this rank's normalised scalar to (value - low) /
// (high - low), squeezed into (0, 1)), so IceT's nearest fragment is the
// rank with the smallest minimum. A ray that took no sample on this piece
// draws nothing (sampled MinIP's mc_noSample; analytic MinIP walks every
// cell a fragment's ray crosses, at least one).
#ifdef MC_NO_SAMPLE_FLAG
  if (mc_noSample)
  {
    discard;
  }
#endif
  gl_FragDepth = clamp(u_mc_depthScale * mc_rayMax + u_mc_depthBias, 0.0, 1.0);
