// mipcast piece: missing_exit
// fills: Cropping::Exit
// mode: augment
// Installed only for input with missing values (NaN/Inf, filled below the
// finite minimum: mipcast.core.prepare): a ray whose value is below the
// finite minimum saw no finite data, so it draws nothing (background; the
// float readout keeps its miss value). Once per ray, after the loop. Hooks
// that start rays at the floor say it themselves (MC_MISSING_FLAG, mip_globals).
#ifdef MC_MISSING_FLAG
  if (mc_rayMissing)
#else
  if (mc_rayMax < u_mc_missingBelow)
#endif
  {
    discard;
  }
