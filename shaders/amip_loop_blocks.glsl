// mipcast piece: amip_loop_blocks
// fills: Shading::Init
// mode: replace
// Analytic MIP with block skipping, used when the transfer functions have a
// floor above the data minimum (the usual clinical window): most blocks then
// lie below the running maximum from the start. A block of u_mc_blockSize^3
// cells whose maximum (the coarse level in in_mask, mipcast/mappers/max_blocks.py)
// is not above the running maximum cannot change the answer and is jumped
// over. Otherwise as amip_loop (floor, ceiling, exact float readout).
// Analytic MinIP runs it mirrored (block minima, a ceiling below the data
// maximum). The cell hooks (amip_max_hooks, amip_min_hooks) decide, besides
// amip_cell's hooks:
//   bool mcCellsBlockSkips(float blockBound, float value)
//       whether a block whose bound (raw: its maximum, or minimum) is
//       blockBound cannot change the running value.
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
  int mc_steps = 2 * int(u_mc_dims.x + u_mc_dims.y + u_mc_dims.z) + 8;  // cells and jumps
  int mc_blockSize = int(u_mc_blockSize);
  float mc_t0 = mc_ray.start;
  mc_rayMax = mcCellsBegin();  // the floor (amip_max_hooks; amip_min_hooks: the ceiling)
  for (int mc_i = 0; mc_i < mc_steps && (mc_i == 0 || mc_t0 < mc_ray.length) && mcCellsGoOn(mc_rayMax); ++mc_i)
  {
    float mc_t1 = min(min(min(mc_tNext.x, mc_tNext.y), mc_tNext.z), mc_ray.length);
    ivec3 mc_cell = mcCellOf(mc_ray, mc_t0, mc_t1);
    ivec3 mc_block = mc_cell / mc_blockSize;
    if (mcCellsBlockSkips(mcRaw(texelFetch(in_mask, mc_block, 0).r), mc_rayMax))
    {
      // Jump to where the ray leaves this block and restart the DDA there
      // (at least to t1, so the walk always moves on).
      vec3 mc_low = vec3(mc_block * mc_blockSize);
      vec3 mc_high = min(mc_low + float(mc_blockSize), u_mc_dims - 1.0);
      vec3 mc_exit = mix((mix(mc_low, mc_high, vec3(greaterThan(mc_ray.dir, vec3(0.0)))) - mc_ray.origin)
                         / mix(mc_ray.dir, vec3(1.0), vec3(mc_ray.still)), vec3(1.0e30), vec3(mc_ray.still));
      mc_t0 = max(mc_t1, min(min(min(mc_exit.x, mc_exit.y), mc_exit.z), mc_ray.length));
      mc_tNext = mcPlanesAfter(mc_ray, mc_t0);
      mc_blocksJumped += 1.0;
      continue;
    }
    mcWalkCell(mc_ray, mc_cell, mc_t1, mc_t0, mc_tNext, mc_rayMax);
  }
  mc_rayMax = mcCellsEnd(mc_rayMax);  // the bounds drawn as the tables' ends
  g_exit = true;
