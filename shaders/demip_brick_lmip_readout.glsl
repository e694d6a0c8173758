// mipcast piece: demip_brick_lmip_readout
// fills: RenderToImage::Exit
// mode: replace
// LMIP in bricks, phase 1 (demip_brick_lmip_hooks): the float readout holds
// the running maximum after this brick (normalised, u_mc_brickChannel 0) or
// whether LMIP's scan ended in this brick (1 or 0, channel 1), shifted by -2
// as float_readout's value (the clear value 1.0 stays "no ray").
  gl_FragData[1] = vec4((u_mc_brickChannel > 0.5 ? mc_lmipEnded : mc_rayMax) - 2.0);
