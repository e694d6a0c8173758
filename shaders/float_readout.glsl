// mipcast piece: float_readout
// fills: RenderToImage::Exit
// mode: replace
// Float readout (RenderToImage with a float "depth" image): write the ray's
// normalised maximum instead of a depth, so it can be read back as float32.
// The value is shifted by -2 so that hits ([-2, -1]) never equal the clear
// value 1.0 that pixels no ray reaches keep; Python undoes the shift.
  gl_FragData[1] = vec4(mc_rayMax - 2.0);
