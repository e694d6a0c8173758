// mipcast piece: foveated_missing_flag
// fills: Base::Exit
// mode: augment
// missing_exit for the masked levels of content-adaptive foveation: a cast
// ray whose value is below the finite minimum saw no finite data, so it
// draws nothing; coarser levels lie beneath, so it is marked
// (mc_drawsNothing) for foveated_paint_beneath to paint what lay beneath
// the volume, or, in a float readout, to draw nothing. Once per ray, after
// the loop.
#ifdef MC_MISSING_FLAG
  if (mc_rayMissing)  // hooks that start rays at the floor say it themselves (mip_globals)
#else
  if (mc_rayMax < u_mc_missingBelow)
#endif
  {
    mc_drawsNothing = true;
  }
