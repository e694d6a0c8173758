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
float mc_cellsFloor;
float mc_cellsCeiling;

float mcCellsBegin()
{
  mc_cellsCeiling = mcRaw(u_mc_skipCeiling);
  mc_cellsFloor = mcRaw(u_mc_skipFloor);
  return mc_cellsFloor;
}

bool mcCellsGoOn(float value)
{
  return value < mc_cellsCeiling;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 corners = max(lo, hi);
  if (u_mc_cornerBound < 0.5 || max(max(corners.x, corners.y), max(corners.z, corners.w)) > value)
  {
    mc_cellsSolved += 1.0;
    value = max(value, mcCellMaximum(lo, hi, u0, du));
  }
}

bool mcCellsBlockSkips(float blockBound, float value)
{
  return blockBound <= value;
}

float mcCellsEnd(float value)
{
  return MC_BOUNDED_NORMALISED(value, mc_cellsFloor, mc_cellsCeiling);
}
