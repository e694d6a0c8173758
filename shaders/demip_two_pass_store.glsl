// mipcast piece: demip_two_pass_store
// fills: RenderToImage::Exit
// mode: replace
// Two-pass DEMIP, pass 1: write the two sample indices into the float
// "depth" image (encoding: demip_two_pass_globals).
  if (mc_firstPacked)
  {
    gl_FragData[1] = vec4(-1.0 - float(mc_firstStart * u_mc_indexBase + mc_firstMax));
  }
  else
  {
    gl_FragData[1] = vec4(2.0 + float(mc_firstMax));
  }
