// mipcast piece: amip_average_hooks
// fills: Picking::Dec
// mode: augment
// Analytic average's cell hooks (see amip_cell): the exact mean of the
// trilinear interpolant along the ray. Each cell adds the integral of its
// cubic d0 + d1 s + d2 s^2 + d3 s^3 over s in [0, 1] times its segment
// length; the mean is the sum over the ray's length. Every cell counts: no
// skipping, no early end. A ray of zero length (grazing an edge) takes the
// value at its entry. For average_color: mc_rayShade is the normalised mean
// (stock VTK's AVERAGE_INTENSITY grey), mc_rayWeight 1 (a ray that hits
// always has a mean).
float mc_rayShade;
float mc_rayWeight;
float mc_cellsLength;
float mc_cellsEntry;

float mcCellsBegin()
{
  mc_cellsLength = 0.0;
  mc_cellsEntry = 1.0e30;
  return 0.0;
}

bool mcCellsGoOn(float value)
{
  return true;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 d = mcCellCubic(lo, hi, u0, du);
  mc_cellsSolved += 1.0;
  mc_cellsEntry = mc_cellsEntry == 1.0e30 ? d.x : mc_cellsEntry;
  value += span * (d.x + 0.5 * d.y + d.z / 3.0 + 0.25 * d.w);
  mc_cellsLength += span;
}

float mcCellsEnd(float value)
{
  mc_rayShade = mcNormalised(mc_cellsLength > 0.0 ? value / mc_cellsLength : mc_cellsEntry);
  mc_rayWeight = 1.0;
  return mc_rayShade;
}
