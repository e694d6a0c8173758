// mipcast piece: amip_max_hooks
// fills: Picking::Dec
// mode: augment
// Analytic MIP's cell hooks (see amip_cell): the exact maximum. The running
// maximum starts at the transfer functions' floor and the walk stops at their
// ceiling (the float readout sets them to -/+1e30). A cell none of whose
// corners is above the running maximum cannot raise it (trilinear values
// never exceed the corners): its cubic is not solved (u_mc_cornerBound 0
// turns this skip off, for measuring).
float mc_cellsCeiling;

float mcCellsBegin()
{
  mc_cellsCeiling = mcRaw(u_mc_ceiling);
  return mcRaw(u_mc_floor);
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

float mcCellsEnd(float value)
{
  return mcNormalised(value);
}
