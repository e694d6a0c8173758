// mipcast piece: depth_composite
// fills: DepthPass::Exit
// mode: augment
// One rank's piece of a volume drawn in a parallel ParaView render view
// (plugin/representation, Z-buffer compositing by IceT): the fragment's depth
// is a decreasing function of the ray's value in data units, the same on
// every rank (u_mc_depthScale, u_mc_depthBias map this rank's normalised
// scalar to 1 - (value - low) / (high - low) over the transfer functions'
// range, squeezed into (0, 1)), so IceT's "keep the nearest fragment" keeps
// the rank with the largest maximum, and that fragment carries its own
// colour. A ray that took no sample on this piece (mc_rayMax still at the
// loop's start value) draws nothing.
  if (mcRaw(mc_rayMax) < -1.0e29)
  {
    discard;
  }
  gl_FragDepth = clamp(u_mc_depthScale * mc_rayMax + u_mc_depthBias, 0.0, 1.0);
