// mipcast piece: average_brick_readout
// fills: RenderToImage::Exit
// mode: replace
// Instead of the float readout, on a brick of a sampled average drawn in
// bricks (mipcast.mappers.bricked_draw, BRICKS "mean"): u_mc_brickChannel
// picks what the brick writes. 0: the mean (as float_readout), 1: the number
// of samples it counted (written -2 - count), 2: the mean opacity of those
// samples, 3: the mean of opacity * s (s VTK's normalised scalar of the
// brick). Python combines the bricks' means weighted by their counts and
// builds the picture's grey from 2 and 3 (exact: sums over disjoint sample sets).
  float mc_brickOut = u_mc_brickChannel < 0.5 ? mc_rayMax - 2.0
      : (u_mc_brickChannel < 1.5 ? -2.0 - mc_rayWeight
      : (u_mc_brickChannel < 2.5 ? mc_rayOpacity / max(mc_rayWeight, 1.0) - 2.0
      : mc_rayOpShade / max(mc_rayWeight, 1.0) - 2.0));
  gl_FragData[1] = vec4(mc_brickOut);
