// mipcast piece: stock_depth_composite
// fills: DepthPass::Exit
// mode: augment
// VTK's own GPU MIP (the "stock" method) drawing one rank's piece in a parallel
// ParaView render view (plugin/representation, IceT's Z-buffer compositing):
// as depth_composite for mipcast's mappers, the fragment's depth decreases with
// the ray's maximum (u_mc_depthScale, u_mc_depthBias: this rank's normalised
// scalar to 1 - (value - low) / (high - low) over the transfer functions'
// range), so IceT keeps the rank with the largest maximum and its colour.
// VTK's MIP loop keeps the ray's maximum in l_maxValue (.w for one component)
// and l_firstValue stays true when the ray took no sample: it draws nothing.
// VTK's sampling is kept as it is (the samples start at this piece's entry).
  if (l_firstValue)
  {
    discard;
  }
  gl_FragDepth = clamp(u_mc_depthScale * l_maxValue.w + u_mc_depthBias, 0.0, 1.0);
