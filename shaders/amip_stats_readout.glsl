// mipcast piece: amip_stats_readout
// fills: RenderToImage::Exit
// mode: replace
// Instead of the float readout's value: one of analytic MIP's work counters
// per ray (u_mc_stat 0: cells walked, 1: cells whose cubic was solved,
// 2: blocks jumped), written as -2 - count * 1e-4 so that the float readout's
// decoding applies (see mipcast/mappers/amip_stats.py).
  float mc_count = u_mc_stat < 0.5 ? mc_cellsWalked : (u_mc_stat < 1.5 ? mc_cellsSolved : mc_blocksJumped);
  gl_FragData[1] = vec4(-2.0 - 1.0e-4 * mc_count);
