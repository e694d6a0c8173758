// mipcast piece: amip_max_hooks
// fills: Picking::Dec
// mode: augment
// Analytic MIP's cell hooks (see amip_cell): the exact maximum. The running
// maximum starts at the transfer functions' floor and the walk stops at their
// ceiling (the float readout sets them to -/+1e30). A cell none of whose
// corners is above the running maximum cannot raise it (trilinear values
// never exceed the corners): its cubic is not solved (u_mc_cornerBound 0
// turns this skip off, for measuring). VTK draws colour and opacity from
// tables that interpolate between texels, so the bounds' own colours are not
// the transfer functions' constant ones: a ray still at the floor (nothing
// higher seen) is drawn as the table's bottom (normalised 0.0), one stopped
// at or above the ceiling as its top (1.0), where the tables hold exactly
// the constant colours (a narrow window would otherwise tint such pixels).
// Missing values (filled below the data, u_mc_missingBelow; -1e30 when none):
// until the ray meets finite data (a cell whose maximum reaches the
// threshold), mc_cellsUnseen lies just below the threshold, and a cell or
// block with a corner above it is not skipped for lying below the floor
// (one min per cell), whatever the opacity at the floor; from then on, and
// from the start without missing values, it is 3.4e38 (no effect). A ray
// that never meets finite data sets mc_rayMissing (MC_MISSING_FLAG,
// mip_globals): missing_exit and foveated_missing_flag draw nothing. (Lifting
// the running maximum from below the threshold to the floor instead, with no
// min per cell, cost a solved cell a select: 8 % at full range.)
#define MC_MISSING_FLAG
#ifndef MC_CELLS_RAW
#define MC_CELLS_RAW mcRaw  // the threshold as a raw texel value (a distributed brick: global_cells' mcGlobalRaw)
#endif
float mc_cellsFloor;
float mc_cellsCeiling;
float mc_cellsMissing;  // raw
float mc_cellsUnseen;   // while the ray has met no finite data, just below mc_cellsMissing; then 3.4e38

float mcCellsBegin()
{
  mc_cellsCeiling = mcRaw(u_mc_skipCeiling);
  mc_cellsFloor = mcRaw(u_mc_skipFloor);
  mc_cellsMissing = u_mc_missingBelow > -1.0e29 ? MC_CELLS_RAW(u_mc_missingBelow) : -3.4e38;
  mc_cellsUnseen = u_mc_missingBelow <= -1.0e29 ? 3.4e38 : mc_cellsMissing - abs(mc_cellsMissing) * 1.0e-6 - 1.0e-30;
  return mc_cellsFloor;
}

bool mcCellsGoOn(float value)
{
  return value < mc_cellsCeiling;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 corners = max(lo, hi);
  float top = max(max(corners.x, corners.y), max(corners.z, corners.w));
  if (u_mc_cornerBound < 0.5 || top > min(value, mc_cellsUnseen))
  {
    mc_cellsSolved += 1.0;
    float cellMax = mcCellMaximum(lo, hi, u0, du);
    mc_cellsUnseen = cellMax >= mc_cellsMissing ? 3.4e38 : mc_cellsUnseen;
    value = max(value, cellMax);
  }
}

bool mcCellsBlockSkips(float blockBound, float value)
{
  return blockBound <= min(value, mc_cellsUnseen);
}

float mcCellsEnd(float value)
{
  mc_rayMissing = mc_cellsUnseen < 3.0e38;
  return MC_BOUNDED_NORMALISED(value, mc_cellsFloor, mc_cellsCeiling);
}
