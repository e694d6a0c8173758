// mipcast piece: stock_depth_composite_min
// fills: DepthPass::Exit
// mode: augment
// stock_depth_composite for VTK's own GPU MinIP (the "stock_minip" method): the
// fragment's depth increases with the ray's minimum (l_minValue, .w for one
// component), so IceT's "keep the nearest fragment" keeps the smallest minimum.
  if (l_firstValue)
  {
    discard;
  }
  gl_FragDepth = clamp(u_mc_depthScale * l_minValue.w + u_mc_depthBias, 0.0, 1.0);
