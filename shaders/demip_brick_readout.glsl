// mipcast piece: demip_brick_readout
// fills: RenderToImage::Exit
// mode: replace
// Distributed DEMIP, phase 2: the float readout holds the whole-ray index k
// of this brick's first same-material sample as -1 - k (exact: integers
// below 2^24; read back as 1 - decoded), or 1.0, the clear value, where
// there is none (read back as NaN).
  gl_FragData[1] = vec4(mc_matchIndex >= 0 ? -1.0 - float(mc_matchIndex) : 1.0);
