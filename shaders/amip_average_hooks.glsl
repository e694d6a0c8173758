// mipcast piece: amip_average_hooks
// fills: Picking::Dec
// mode: augment
// Analytic average's cell hooks (see amip_cell): the exact mean of the
// trilinear interpolant along the ray. Each cell adds the integral of its
// cubic d0 + d1 s + d2 s^2 + d3 s^3 over s in [0, 1] times its segment
// length; the mean is the sum over the ray's length. Every cell counts: no
// skipping, no early end. A ray of zero length (grazing an edge) takes the
// value at its entry. The ray's value (mc_rayMax, coloured by average_color,
// and the float readout) is the normalised mean, clamped to the counted
// cells' corners (rounding kept inside what the interpolant can take);
// mc_rayWeight 1 (a ray that hits always has a mean). Input with missing
// values takes amip_average_missing_hooks instead.
float mc_rayWeight = 1.0;
float mc_cellsLength;
float mc_cellsEntry;
vec2 mc_cellsBounds;  // smallest and largest corner of the counted cells

float mcCellsBegin()
{
  mc_cellsLength = 0.0;
  mc_cellsEntry = 1.0e30;
  mc_cellsBounds = vec2(1.0e30, -1.0e30);
  return 0.0;
}

bool mcCellsGoOn(float value)
{
  return true;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 d = mcCellCubic(lo, hi, u0, du);
  vec4 corners = min(lo, hi);
  vec4 tops = max(lo, hi);
  mc_cellsBounds = vec2(min(mc_cellsBounds.x, min(min(corners.x, corners.y), min(corners.z, corners.w))),
                        max(mc_cellsBounds.y, max(max(tops.x, tops.y), max(tops.z, tops.w))));
  mc_cellsSolved += 1.0;
  mc_cellsEntry = mc_cellsEntry == 1.0e30 ? d.x : mc_cellsEntry;
  value += span * (d.x + 0.5 * d.y + d.z / 3.0 + 0.25 * d.w);
  mc_cellsLength += span;
}

float mcCellsEnd(float value)
{
  float raw = mc_cellsLength > 0.0 ? value / mc_cellsLength : mc_cellsEntry;
  if (mc_cellsBounds.x <= mc_cellsBounds.y)
  {
    // the mean lies between the counted cells' corners: clamping removes the rounding that VTK's
    // normalisation of a constant volume (zero range) would amplify
    raw = clamp(raw, mc_cellsBounds.x, mc_cellsBounds.y);
  }
  return mcNormalised(raw);
}
