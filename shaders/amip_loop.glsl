// mipcast piece: amip_loop
// fills: Shading::Init
// mode: replace
// The exact projections' cell walk (3D DDA, helpers in amip_cell): every
// crossed cell goes to the projection's mcCell hook (amip_max_hooks: the
// exact maximum; amip_min_hooks, amip_average_hooks), which keeps the running
// value in mc_rayMax. Analytic MIP uses it when the transfer functions have
// no floor above the data minimum (see amip_loop_blocks). For display,
// u_mc_skipFloor / u_mc_skipCeiling (normalised) are where the transfer functions stop
// changing: MIP's running maximum starts at the floor and the walk ends once
// it reaches the ceiling (mcCellsBegin / mcCellsGoOn), which leaves the colour
// unchanged. The float readout sets them to -/+1e30, so it stays exact in data units.
// (not on a distributed brick: its walk casts the whole volume's ray, global_cells)
#if defined(MC_RAY_MEND) && !defined(MC_GLOBAL_CELLS)
  if (!mcMendRay())  // VTK's set-up from a fragment off the box (ray_mend)
  {
    MC_DRAW_NOTHING(g_fragColor)  // the pixel's line misses the box
  }
#endif
  McRay mc_ray = mcBeginRay();
  if (mc_drawsNothing)
  {
    return g_fragColor;  // (mip_globals: MC_DRAW_NOTHING)
  }
  vec3 mc_tNext = mcPlanesAfter(mc_ray, mc_ray.start);
  int mc_steps = int(u_mc_dims.x + u_mc_dims.y + u_mc_dims.z) + 3;
  float mc_t0 = mc_ray.start;
  mc_rayMax = mcCellsBegin();
  for (int mc_i = 0; mc_i < mc_steps && (mc_i == 0 || mc_t0 < mc_ray.length) && mcCellsGoOn(mc_rayMax); ++mc_i)
  {
    float mc_t1 = min(min(min(mc_tNext.x, mc_tNext.y), mc_tNext.z), mc_ray.length);
    mcWalkCell(mc_ray, mcCellOf(mc_ray, mc_t0, mc_t1), mc_t1, mc_t0, mc_tNext, mc_rayMax);
  }
  mc_rayMax = mcCellsEnd(mc_rayMax);
  g_exit = true;
