// mipcast piece: demip_brick_lmip_hooks
// fills: Picking::Dec
// mode: augment
// LMIP with DEMIP drawn in bricks, phase 1 on one brick (mipcast/mappers/
// demip_ordered_bricks.py), hooks for sampled_loop with global_phase (the whole
// volume's sample positions and indices). The bricks are drawn front to back
// (mipcast.mappers.brick_rays.visibility_order); each continues LMIP's scan
// of demip_lmip_hooks where the bricks in front of it left it: the running
// maximum of the samples in front (mc_globalMax, read by demip_brick_fetch
// from the float texture; > 1e29: no sample yet) and LMIP's threshold
// u_mc_brickLocal (this brick's normalised scalar, from the transfer
// functions over the WHOLE volume's range). The scan ends before the first
// sample below a running maximum above the threshold (mc_lmipEnded 1): the
// bricks behind leave that ray alone (the CPU keeps its maximum). The
// readout (demip_brick_lmip_readout) gives the running maximum (channel 0)
// or the end flag (channel 1, u_mc_brickChannel). The maximum carried from
// the bricks in front is another brick's value, read from another texture
// through other normalisations: the same point's value differs between
// bricks by float32 rounding (i16 data with a mask, filled as float: 2.2e-6
// of the range). A sample within mc_carriedTie (1e-5 of the whole range)
// below the carried maximum (the same point again, as nearest-neighbour
// interpolation takes it) is no fall. Until 2026-12-05 it was: the scan
// ended at a brick's first sample, up to 0.6 of the range off.
float mc_globalMax;
float mc_lmipLocalRaw;
float mc_lmipEnded;
float mc_carried;
float mc_carriedTie;

void mcBeginRay(inout int first, inout int count)
{
  mc_lmipLocalRaw = mcRaw(u_mc_brickLocal);
  mc_rayMax = mc_globalMax < 1.0e29 ? mcRaw(mc_globalMax) : -1.0e30;
  mc_carried = mc_rayMax;
  mc_carriedTie = 1.0e-5 / abs(mcGlobalNormalised(1.0) - mcGlobalNormalised(0.0));  // raw units
  mc_lmipEnded = 0.0;
}

bool mcSample(float value, int i)
{
  bool tie = mc_rayMax == mc_carried && value >= mc_carried - mc_carriedTie;
  if (value < mc_rayMax && mc_rayMax > mc_lmipLocalRaw && !tie)
  {
    mc_lmipEnded = 1.0;
    return false;
  }
  mc_rayMax = max(mc_rayMax, value);
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_rayMax);
}
