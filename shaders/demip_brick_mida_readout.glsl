// mipcast piece: demip_brick_mida_readout
// fills: RenderToImage::Exit
// mode: replace
// MIDA in bricks (demip_brick_mida_hooks): the float readout holds minus one
// number of the brick's compositing state, as it is (all in [0, 1]; +1, the
// clear value, stays "no ray"): u_mc_brickChannel 0, 1, 2 the brick's
// colour, 3 the accumulated opacity, 4 the product of its betas, 5 the
// running maximum of the material.
  int mc_channel = int(u_mc_brickChannel + 0.5);
  float mc_out = mc_channel < 3 ? mc_sum[mc_channel] : (mc_channel == 3 ? mc_sum.a
                 : (mc_channel == 4 ? mc_betaProduct : mc_runMaterial));
  gl_FragData[1] = vec4(-mc_out);
