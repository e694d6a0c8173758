// mipcast piece: amip_loop
// fills: Shading::Init
// mode: replace
// Analytic MIP: the exact maximum of the trilinear interpolant along the ray,
// walked cell by cell (3D DDA, helpers in amip_cell). Used when the transfer
// functions have no floor above the data minimum (see amip_loop_blocks).
// For display, u_mc_floor / u_mc_ceiling (normalised) are where the transfer
// functions stop changing: the running maximum starts at the floor and the
// walk ends once it reaches the ceiling, which leaves the colour unchanged.
// The float readout sets them to -/+1e30, so it stays exact in data units.
  McRay mc_ray = mcBeginRay();
  vec3 mc_tNext = mcPlanesAfter(mc_ray, mc_ray.start);
  int mc_steps = int(u_mc_dims.x + u_mc_dims.y + u_mc_dims.z) + 3;
  float mc_t0 = mc_ray.start;
  float mc_ceiling = mcRaw(u_mc_ceiling);
  mc_rayMax = mcRaw(u_mc_floor);
  for (int mc_i = 0; mc_i < mc_steps && (mc_i == 0 || mc_t0 < mc_ray.length) && mc_rayMax < mc_ceiling; ++mc_i)
  {
    float mc_t1 = min(min(min(mc_tNext.x, mc_tNext.y), mc_tNext.z), mc_ray.length);
    mcWalkCell(mc_ray, mcCellOf(mc_ray, mc_t0, mc_t1), mc_t1, mc_t0, mc_tNext, mc_rayMax);
  }
  mc_rayMax = mcNormalised(mc_rayMax);
  g_exit = true;
