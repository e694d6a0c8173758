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
// Missing values (filled above the data, u_mc_missingAbove; 1e30 when none):
// as amip_max_hooks, mirrored (a ray that never meets finite data sets
// mc_rayMissing: missing_exit_above draws nothing).
#define MC_MISSING_FLAG
#ifndef MC_CELLS_RAW
#define MC_CELLS_RAW mcRaw  // the threshold as a raw texel value (a distributed brick: global_cells' mcGlobalRaw)
#endif
float mc_cellsFloor;
float mc_cellsCeiling;
float mc_cellsMissing;  // raw
float mc_cellsUnseen;   // while the ray has met no finite data, just above mc_cellsMissing; then -3.4e38

float mcCellsBegin()
{
  mc_cellsFloor = mcRaw(u_mc_skipFloor);
  mc_cellsCeiling = mcRaw(u_mc_skipCeiling);
  mc_cellsMissing = u_mc_missingAbove < 1.0e29 ? MC_CELLS_RAW(u_mc_missingAbove) : 3.4e38;
  mc_cellsUnseen = u_mc_missingAbove >= 1.0e29 ? -3.4e38 : mc_cellsMissing + abs(mc_cellsMissing) * 1.0e-6 + 1.0e-30;
  return mc_cellsCeiling;
}

bool mcCellsGoOn(float value)
{
  return value > mc_cellsFloor;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 corners = min(lo, hi);
  float bottom = min(min(corners.x, corners.y), min(corners.z, corners.w));
  if (u_mc_cornerBound < 0.5 || bottom < max(value, mc_cellsUnseen))
  {
    mc_cellsSolved += 1.0;
    float cellMin = -mcCellMaximum(-lo, -hi, u0, du);
    mc_cellsUnseen = cellMin <= mc_cellsMissing ? -3.4e38 : mc_cellsUnseen;
    value = min(value, cellMin);
  }
}

bool mcCellsBlockSkips(float blockBound, float value)
{
  return blockBound >= max(value, mc_cellsUnseen);
}

float mcCellsEnd(float value)
{
  mc_rayMissing = mc_cellsUnseen > -3.0e38;
  return MC_BOUNDED_NORMALISED(value, mc_cellsFloor, mc_cellsCeiling);
}
