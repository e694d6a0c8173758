// mipcast piece: demip_brick_attenuated_readout
// fills: RenderToImage::Exit
// mode: replace
// Attenuated MIP in bricks (demip_brick_attenuated_hooks): the float readout
// holds minus the brick's best attenuated material (u_mc_brickChannel 0;
// +1, the clear value "no ray", where the brick had no sample) or minus the
// material crossed after this brick (channel 1), as they are (no shift:
// the crossed sum goes on to the next brick bit for bit).
  gl_FragData[1] = vec4(-(u_mc_brickChannel > 0.5 ? mc_crossed : mc_rayMax));
