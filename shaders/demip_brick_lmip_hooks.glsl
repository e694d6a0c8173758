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
// or the end flag (channel 1, u_mc_brickChannel).
float mc_globalMax;
float mc_lmipLocalRaw;
float mc_lmipEnded;

void mcBeginRay(inout int first, inout int count)
{
  mc_lmipLocalRaw = mcRaw(u_mc_brickLocal);
  mc_rayMax = mc_globalMax < 1.0e29 ? mcRaw(mc_globalMax) : -1.0e30;
  mc_lmipEnded = 0.0;
}

bool mcSample(float value, int i)
{
  if (value < mc_rayMax && mc_rayMax > mc_lmipLocalRaw)
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
