// mipcast piece: amip_min_hooks
// fills: Picking::Dec
// mode: augment
// Analytic MinIP's cell hooks (see amip_cell): the exact minimum of the
// trilinear interpolant, the maximum of the negated cell (negating the
// corners negates the cubic exactly). Mirrored bounds: the running minimum
// starts at the transfer functions' ceiling and the walk stops at their
// floor (the float readout sets them to +/-1e30); a cell none of whose
// corners is below the running minimum cannot lower it (u_mc_cornerBound 0
// turns this skip off). VTK draws colour and opacity from tables that
// interpolate between texels, so the bounds' own colours are not the
// transfer functions' constant ones: a ray still at the ceiling (nothing
// lower seen) is drawn as the table's top (normalised 1.0), one stopped at
// or below the floor as its bottom (0.0), where the tables hold exactly the
// constant colours (a narrow window would otherwise grey every such pixel).
float mc_cellsFloor;
float mc_cellsCeiling;

float mcCellsBegin()
{
  mc_cellsFloor = mcRaw(u_mc_skipFloor);
  mc_cellsCeiling = mcRaw(u_mc_skipCeiling);
  return mc_cellsCeiling;
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

bool mcCellsBlockSkips(float blockBound, float value)
{
  return blockBound >= value;
}

float mcCellsEnd(float value)
{
  return MC_BOUNDED_NORMALISED(value, mc_cellsFloor, mc_cellsCeiling);
}
