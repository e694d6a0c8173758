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
// mc_rayWeight 1 (a ray that hits always has a mean).
// Missing data (MC_AVERAGE_MISSING, defined by amip_average_missing only
// while the input holds missing values: llvmpipe runs both sides of a
// branch, and this code merely present made the average 5x slower): missing
// voxels are filled below u_mc_missingBelow (normalised; mipcast.core.prepare),
// and the mean is taken over the part of the ray where the (filled)
// interpolant is at or above it, the limit of the sampled average's rule (a
// sample below it is missing). A cell whose corners are all above it counts
// whole, as above; in a cell with a corner below it the cubic is split at its
// derivative's roots into monotone pieces, each piece's crossing of the
// threshold found by 24 bisections (float32's resolution of [0, 1]), and the
// covered parts add their integral and length, their bounds running from the
// threshold to the largest corner. A ray with no covered part has weight 0
// (background).
float mc_rayWeight = 1.0;
float mc_cellsLength;
float mc_cellsEntry;
vec2 mc_cellsBounds;  // smallest and largest corner of the counted cells

#ifdef MC_AVERAGE_MISSING
float mc_cellsMissing;

// The cubic's mean over [a, b] (no cancellation for short pieces).
float mcCubicMean(vec4 d, float a, float b)
{
  return d.x + 0.5 * d.y * (a + b) + d.z * (a * a + a * b + b * b) / 3.0 + 0.25 * d.w * (a + b) * (a * a + b * b);
}

// One bisection step of the bracket (lo, hi) of the cubic's crossing of level
// (the cubic at lo is below level exactly when below0).
vec2 mcHalve(vec4 d, float level, bool below0, vec2 bracket)
{
  float m = 0.5 * (bracket.x + bracket.y);
  return (mcCubic(d, m) < level) == below0 ? vec2(m, bracket.y) : vec2(bracket.x, m);
}

// The part of [s0, s1] (the cubic monotone there) where it is >= level:
// adds (its integral, its length) to covered.
void mcCoveredPiece(vec4 d, float s0, float s1, float level, inout vec2 covered)
{
  bool below0 = mcCubic(d, s0) < level;
  bool below1 = mcCubic(d, s1) < level;
  if (s1 <= s0 || (below0 && below1))
  {
    return;
  }
  float a = s0;
  float e = s1;
  if (below0 != below1)
  {
    // 24 halvings (float32's resolution of [0, 1]); a loop, which llvmpipe skips where no lane needs it
    vec2 b = vec2(s0, s1);
    for (int k = 0; k < 24; ++k)
    {
      b = mcHalve(d, level, below0, b);
    }
    float r = 0.5 * (b.x + b.y);
    a = below0 ? r : s0;
    e = below0 ? s1 : r;
  }
  covered += vec2((e - a) * mcCubicMean(d, a, e), e - a);
}

// (integral, length) over s in [0, 1] of the part where the cubic d is >= level.
vec2 mcCoveredCell(vec4 d, float level)
{
  vec2 r = mcCriticalPoints(d);
  vec2 covered = vec2(0.0);
  mcCoveredPiece(d, 0.0, min(r.x, r.y), level, covered);
  mcCoveredPiece(d, min(r.x, r.y), max(r.x, r.y), level, covered);
  mcCoveredPiece(d, max(r.x, r.y), 1.0, level, covered);
  return covered;
}
#endif

float mcCellsBegin()
{
  mc_cellsLength = 0.0;
  mc_cellsEntry = 1.0e30;
  mc_cellsBounds = vec2(1.0e30, -1.0e30);
#ifdef MC_AVERAGE_MISSING
  mc_cellsMissing = u_mc_missingBelow > -1.0e29 ? mcRaw(u_mc_missingBelow) : -1.0e30;
#endif
  return 0.0;
}

bool mcCellsGoOn(float value)
{
  return true;
}

void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
{
  vec4 corners = min(lo, hi);
#ifdef MC_AVERAGE_MISSING
  if (min(min(corners.x, corners.y), min(corners.z, corners.w)) < mc_cellsMissing)
  {
    vec4 m = mcCellCubic(lo, hi, u0, du);
    vec2 covered = mcCoveredCell(m, mc_cellsMissing);
    vec4 tops = max(lo, hi);
    if (covered.y > 0.0)  // its covered part lies between the threshold and its largest corner
    {
      mc_cellsBounds = vec2(min(mc_cellsBounds.x, mc_cellsMissing),
                            max(mc_cellsBounds.y, max(max(tops.x, tops.y), max(tops.z, tops.w))));
    }
    mc_cellsSolved += 1.0;
    mc_cellsEntry = mc_cellsEntry == 1.0e30 && m.x >= mc_cellsMissing ? m.x : mc_cellsEntry;
    value += span * covered.x;
    mc_cellsLength += span * covered.y;
    return;
  }
#endif
  vec4 d = mcCellCubic(lo, hi, u0, du);
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
#ifdef MC_AVERAGE_MISSING
  mc_rayWeight = mc_cellsLength <= 0.0 && mc_cellsEntry == 1.0e30 && mc_cellsMissing > -1.0e30 ? 0.0 : 1.0;
#endif
  return mcNormalised(raw);
}
