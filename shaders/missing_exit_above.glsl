// mipcast piece: missing_exit_above
// fills: Cropping::Exit
// mode: augment
// missing_exit mirrored for minimum projections: missing values (NaN/Inf)
// are filled above the finite maximum (mipcast.core.prepare, fill_side
// "above"), so a ray whose value is above the finite maximum saw no finite
// data and draws nothing (background; the float readout keeps its miss
// value). Once per ray, after the loop. Hooks that start rays at the ceiling
// say it themselves (MC_MISSING_FLAG, mip_globals).
#ifdef MC_MISSING_FLAG
  if (mc_rayMissing)
#else
  if (mc_rayMax > u_mc_missingAbove)
#endif
  {
    discard;
  }
