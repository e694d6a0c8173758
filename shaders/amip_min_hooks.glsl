// mipcast piece: amip_min_hooks
// fills: Picking::Dec
// mode: augment
// Analytic MinIP's cell hooks (see amip_cell): the exact minimum of the
// trilinear interpolant, the maximum of the negated cell (negating the
// corners negates the cubic exactly). Mirrored bounds: the running minimum
// starts at the transfer functions' ceiling and the walk stops at their
// floor (the float readout sets them to +/-1e30); a cell none of whose
// corners is below the running minimum cannot lower it (u_mc_cornerBound 0
// turns this skip off).
float mc_cellsFloor;

float mcCellsBegin()
{
  mc_cellsFloor = mcRaw(u_mc_floor);
  return mcRaw(u_mc_ceiling);
}

bool mcCellsGoOn(float value)
{
  return value > mc_cellsFloor;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 corners = min(lo, hi);
  if (u_mc_cornerBound < 0.5 || min(min(corners.x, corners.y), min(corners.z, corners.w)) < value)
  {
    mc_cellsSolved += 1.0;
    value = min(value, -mcCellMaximum(-lo, -hi, u0, du));
  }
}

float mcCellsEnd(float value)
{
  return mcNormalised(value);
}
