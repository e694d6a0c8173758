// mipcast piece: demip_readout
// fills: RenderToImage::Exit
// mode: replace
// Float readout of a DEMIP ray (see float_readout): the normalised maximum,
// or with u_mc_readDepth = 1 the normalised depth of the same-material
// sample. Both are shifted by -2 (hits in [-2, -1]); a ray without a DEMIP
// term writes 1.0, the clear value, so that it reads back as NaN.
  if (u_mc_readDepth > 0.5)
  {
    gl_FragData[1] = vec4(mc_matchIndex >= 0 ? mc_depth - 2.0 : 1.0);
  }
  else
  {
    gl_FragData[1] = vec4(mc_rayMax - 2.0);
  }
