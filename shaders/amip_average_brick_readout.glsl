// mipcast piece: amip_average_brick_readout
// fills: RenderToImage::Exit
// mode: replace
// Instead of the float readout, on a brick of an analytic average drawn in
// bricks (mipcast.mappers.bricked_draw, BRICKS "mean"): u_mc_brickChannel
// 0 writes the mean (as float_readout), otherwise the length of the ray
// counted in the brick, in point-index units (the walk's texture-space
// length times mc_indexPerStep: one unit for every brick), written as
// -2 - length. Python combines the bricks' means weighted by these lengths.
  float mc_brickOut = u_mc_brickChannel < 0.5 ? mc_rayMax - 2.0
      : -2.0 - mc_cellsLength * mc_indexPerStep;
  gl_FragData[1] = vec4(mc_brickOut);
