// mipcast piece: amip_cell
// fills: Shading::Dec
// mode: augment
// The exact projections' building blocks, shared by their ray loops (amip_loop,
// amip_loop_blocks): the ray in index space, one DDA step over a cell, the
// cubic of the trilinear interpolant inside a cell and its exact maximum;
// what a cell adds to the ray's value is the projection's mcCell hook. The cell's
// corner values come from mcCellCorners (amip_corners or, from a texture
// holding four corners per texel, amip_corners_packed).
//
// Index space: point i sits at texture coordinate (i + 0.5) / N, so
// p(t) = origin + t * dir with t the texture-space length along the ray.
// Work counters, read by the amip_stats_readout piece (mipcast/mappers/amip_stats.py).
// The power of two nearest below VTK's texture scale (raw texel -> normalised), set once per ray in
// mcBeginRay and used by mcCriticalPoints: scaling by it is exact, so every brick of a distributed volume,
// whatever its own texture scale, finds the roots one texture finds.
float mc_cubicScale = 1.0;

float mc_cellsWalked = 0.0;
float mc_cellsSolved = 0.0;
float mc_blocksJumped = 0.0;
// Point-index units per unit of the walk's ray parameter (|McRay.dir|), set in mcBeginRay.
float mc_indexPerStep = 1.0;

struct McRay
{
  vec3 origin;
  vec3 dir;
  bvec3 still;     // axes the ray runs parallel to
  vec3 tDelta;     // t between voxel planes, per axis
  float start;     // t where the walk starts: 0, or the clipped entry
  float length;    // t where the ray leaves the point bounds, is terminated or clipped
  ivec3 firstCell; // the cells the walk may visit (whole-volume indices on a distributed brick)
  ivec3 lastCell;
};

// Exact maximum over s in [0, 1] of the trilinear interpolant of one cell
// along u(s) = u0 + s * du (local cell coordinates). lo/hi hold the corner
// values at x = 0 / x = 1, ordered (y,z) = (0,0), (1,0), (0,1), (1,1).
// The interpolant is the cubic d0 + d1 s + d2 s^2 + d3 s^3, built by
// lerping along x (linear in s), then y (quadratic), then z (cubic).
float mcCubic(vec4 d, float s)
{
  return d.x + s * (d.y + s * (d.z + s * d.w));
}

vec4 mcCellCubic(vec4 lo, vec4 hi, vec3 u0, vec3 du)
{
  vec4 a = lo + (hi - lo) * u0.x;          // x-lerped edges at s = 0
  vec4 b = (hi - lo) * du.x;               // ... and their slope in s
  vec2 p0 = a.yw - a.xz;                   // y-differences (k = 0, 1), linear in s
  vec2 p1 = b.yw - b.xz;
  vec2 g0 = a.xz + p0 * u0.y;              // y-lerped: quadratic g0 + g1 s + g2 s^2
  vec2 g1 = b.xz + p0 * du.y + p1 * u0.y;
  vec2 g2 = p1 * du.y;
  vec3 q = vec3(g0.y - g0.x, g1.y - g1.x, g2.y - g2.x);
  return vec4(g0.x + q.x * u0.z,
              g1.x + q.x * du.z + q.y * u0.z,
              g2.x + q.y * du.z + q.z * u0.z,
              q.z * du.z);
}

// The cubic's critical points in [0, 1]: the roots of d1 + 2 d2 s + 3 d3 s^2
// by the cancellation-free formula, on the derivative scaled by
// mc_cubicScale, near VTK's normalised units (float32 texel values far from
// 1, 1e20 or 1e-20, would overflow in qb * qb or fall below the 1e-20 guards
// and lose the maximum). A power of two set once per ray: exact (the same
// roots as unscaled where those were right), and one multiply per cell riding
// on the formula's own multiplies by 2 and 3 (dividing by the largest
// coefficient instead cost the walk 15 %). A missing or out-of-range root is
// clamped into [0, 1], which only re-tests a point of the segment (never
// above the true maximum); a ~ 0 (quadratic or linear cubic) and tiny
// segments need no special case.
vec2 mcCriticalPoints(vec4 d)
{
  vec3 k = mc_cubicScale * vec3(1.0, 2.0, 3.0);
  float c1 = k.x * d.y;
  float qa = k.z * d.w;
  float qb = k.y * d.z;
  float disc = max(qb * qb - 4.0 * qa * c1, 0.0);
  float qq = -0.5 * (qb + (qb < 0.0 ? -1.0 : 1.0) * sqrt(disc));
  float r1 = abs(qa) > 1.0e-20 ? qq / qa : 0.0;
  float r2 = abs(qq) > 1.0e-20 ? c1 / qq : 0.0;
  return clamp(vec2(r1, r2), 0.0, 1.0);
}

float mcCellMaximum(vec4 lo, vec4 hi, vec3 u0, vec3 du)
{
  vec4 d = mcCellCubic(lo, hi, u0, du);
  vec2 r = mcCriticalPoints(d);
  float best = max(d.x, d.x + d.y + d.z + d.w);
  best = max(best, mcCubic(d, r.x));
  return max(best, mcCubic(d, r.y));
}

// Ray parameters of the next voxel plane per axis after parameter t; 1e30
// on axes the ray runs parallel to.
#ifdef MC_GLOBAL_CELLS
// On a distributed brick: from the cell the walk starts in, each plane's
// parameter from its index ((plane - origin) / dir, as every later step).
vec3 mcPlanesAfter(McRay ray, float t)
{
  // the cell the ray enters at t: on an axis whose voxel plane it crosses at t
  // (within the walk's tie tolerance) the cell beyond the plane
  vec3 here = ray.origin + t * ray.dir;
  vec3 nearest = floor(here + 0.5);
  bvec3 onPlane = lessThanEqual(abs(here - nearest), (abs(t) * 1.0e-6 + 1.0e-7) * abs(ray.dir) + 1.0e-6);
  vec3 entered = mix(floor(here), nearest - vec3(lessThan(ray.dir, vec3(0.0))), vec3(onPlane));
  vec3 cell = vec3(clamp(ivec3(entered), ray.firstCell, ray.lastCell));
  vec3 plane = cell + vec3(greaterThan(ray.dir, vec3(0.0)));
  return mix((plane - ray.origin) / mix(ray.dir, vec3(1.0), vec3(ray.still)), vec3(1.0e30), vec3(ray.still));
}
#else
vec3 mcPlanesAfter(McRay ray, float t)
{
  vec3 here = ray.origin + t * ray.dir;
  vec3 plane = mix(floor(here) + 1.0, ceil(here) - 1.0, vec3(lessThan(ray.dir, vec3(0.0))));
  return mix(t + (plane - here) / mix(ray.dir, vec3(1.0), vec3(ray.still)), vec3(1.0e30), vec3(ray.still));
}
#endif

// The ray from its true entry (g_dataPos is one jitter step further in) to
// where it leaves the point bounds or reaches the depth-buffer end; with
// clipping planes, a cropping box or a slab (mcClipRange) the walk runs
// exactly from the clipped entry (start) to the clipped exit (length), and a
// ray with nothing left draws nothing. With cropping regions (clip_regions)
// a ray none of whose pieces between the cropping planes is visible draws
// nothing, and mcWalkCell hands only the visible pieces of each cell to the
// hook.
#ifdef MC_CROP_REGIONS
// The cropping planes in index space (set in mcBeginRay).
vec3 mc_cropLowIndex;
vec3 mc_cropHighIndex;
#endif

#ifdef MC_GLOBAL_CELLS
// A distributed brick (global_cells): the whole volume's ray, t = 0 at the
// whole box's entry, walked over this brick's cells [u_mc_brickLo,
// u_mc_brickHi - 1] from where it enters the brick's box (not before the
// near-plane cap, the camera inside the volume) to where it leaves.
McRay mcBeginRay()
{
  mc_cubicScale = exp2(floor(log2(min(in_volume_scale[0].r, 1.0e30))));
  McRay ray;
  vec3 entry;
  vec3 dir;
  float capStart;
  if (!mcGlobalRay(entry, dir, capStart))
  {
    MC_DRAW_NOTHING(ray)  // the ray misses the whole volume (or leaves it before the near-plane cap)
  }
  ray.origin = entry;
  ray.dir = dir;
  ray.still = lessThan(abs(ray.dir), vec3(1.0e-20));
  ray.tDelta = mix(1.0 / max(abs(ray.dir), vec3(1.0e-20)), vec3(1.0e30), vec3(ray.still));
  vec3 safe = mix(ray.dir, vec3(1.0), vec3(ray.still));
  vec3 a = (u_mc_brickLo - ray.origin) / safe;
  vec3 b = (u_mc_brickHi - ray.origin) / safe;
  vec3 inside = vec3(greaterThanEqual(ray.origin, u_mc_brickLo)) * vec3(lessThanEqual(ray.origin, u_mc_brickHi));
  vec3 lo = mix(min(a, b), mix(vec3(1.0e30), vec3(-1.0e30), inside), vec3(ray.still));
  vec3 hi = mix(max(a, b), mix(vec3(-1.0e30), vec3(1.0e30), inside), vec3(ray.still));
  vec3 wa = (u_mc_wholeHi - ray.origin) / safe;
  vec3 wb = (u_mc_wholeLo - ray.origin) / safe;
  vec3 whole = mix(max(wa, wb), vec3(1.0e30), vec3(ray.still));
  ray.start = max(max(max(lo.x, lo.y), lo.z), capStart);
  ray.length = min(min(min(hi.x, hi.y), hi.z), min(min(whole.x, whole.y), whole.z));
  if (ray.start > ray.length)
  {
    MC_DRAW_NOTHING(ray)  // the whole ray passes this brick by
  }
  ray.firstCell = ivec3(u_mc_brickLo);
  ray.lastCell = max(ivec3(u_mc_brickHi) - 1, ray.firstCell);
  return ray;
}
#else
McRay mcBeginRay()
{
  mc_cubicScale = exp2(floor(log2(min(in_volume_scale[0].r, 1.0e30))));
  McRay ray;
  vec3 dims = u_mc_dims;
  vec3 dirTex = normalize(g_dirStep);
  vec3 entryTex = g_dataPos - g_rayJitter;
  vec2 box = mcLineThroughBox(entryTex, dirTex, in_texMin[0], in_texMax[0]);
  float shift = mcEntryShift(box, 1.0);  // a start off the box's entry along its line (mip_globals)
  entryTex += shift * dirTex;
  ray.length = max(0.0, box.y - shift);
  ray.length = min(ray.length, g_terminatePointMax * length(g_dirStep) + length(g_rayJitter) - shift);
  ray.start = 0.0;
#ifdef MC_CLIPPING
  if (u_mc_clipCount > 0)
  {
    mcClipRange(entryTex, dirTex, ray.start, ray.length);
    if (ray.start > ray.length)
    {
      MC_DRAW_NOTHING(ray)  // clipped away: nothing of the ray is left
    }
  }
#endif
  ray.origin = entryTex * dims - 0.5;
  ray.dir = dirTex * dims;
  mc_indexPerStep = length(ray.dir);
  ray.still = lessThan(abs(ray.dir), vec3(1.0e-20));
  ray.tDelta = mix(1.0 / max(abs(ray.dir), vec3(1.0e-20)), vec3(1.0e30), vec3(ray.still));
  ray.firstCell = ivec3(0);
  ray.lastCell = ivec3(dims) - 2;
#ifdef MC_CROP_REGIONS
  mc_cropLowIndex = u_mc_cropLow * dims - 0.5;
  mc_cropHighIndex = u_mc_cropHigh * dims - 0.5;
  // the walk runs from the first visible piece's start to the last one's end
  mcCropVisibleHull(ray.origin, ray.dir, mc_cropLowIndex, mc_cropHighIndex, ray.start, ray.length);
  if (ray.start > ray.length)
  {
    MC_DRAW_NOTHING(ray)  // the ray crosses hidden cropping regions only
  }
#endif
  return ray;
}
#endif

// The cell holding the segment [t0, t1] (by its midpoint: robust at ties).
ivec3 mcCellOf(McRay ray, float t0, float t1)
{
  return clamp(ivec3(floor(ray.origin + (0.5 * (t0 + t1)) * ray.dir)), ray.firstCell, ray.lastCell);
}

// The projection's hooks (one cell-hook piece per exact projection fills
// Picking::Dec and defines them: amip_max_hooks, amip_min_hooks,
// amip_average_hooks; declared here, defined after this piece):
//   float mcCellsBegin()              the running value before the first cell
//   bool mcCellsGoOn(float value)     false: no later cell can change the picture
//   void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value)
//       one crossed cell: corners lo/hi, the segment u0 + s du (s in [0, 1],
//       local cell coordinates) of length span (texture units)
//   float mcCellsEnd(float value)     the ray's normalised value (for mc_rayMax)
float mcCellsBegin();
bool mcCellsGoOn(float value);
void mcCell(vec4 lo, vec4 hi, vec3 u0, vec3 du, float span, inout float value);
float mcCellsEnd(float value);

#ifdef MC_CROP_REGIONS
// The piece of the cell's segment from a to the next cropping plane (or t1):
// to the hook if its region (at its midpoint) is visible; a moves to its end.
void mcCropCellPiece(McRay ray, ivec3 cell, vec4 lo, vec4 hi, inout float a, float t1, inout float value)
{
  float b = mcCropNextCut(ray.origin, ray.dir, mc_cropLowIndex, mc_cropHighIndex, a, t1);
  if (mcCropRegionVisible(ray.origin + (0.5 * (a + b)) * ray.dir, mc_cropLowIndex, mc_cropHighIndex))
  {
    mcCell(lo, hi, ray.origin + a * ray.dir - vec3(cell), (b - a) * ray.dir, b - a, value);
  }
  a = b;
}
#endif

// One DDA step: the segment [t0, t1] in `cell` goes to the projection's
// mcCell hook with the cell's corners; then every axis whose plane is
// reached steps (ties at edges and corners step together) and t0 moves to t1.
void mcWalkCell(McRay ray, ivec3 cell, float t1, inout float t0, inout vec3 tNext, inout float rayMax)
{
  vec4 lo;
  vec4 hi;
#ifdef MC_GLOBAL_CELLS
  mcCellCorners(cell - ray.firstCell, lo, hi);  // the brick's texture starts at its first point
#else
  mcCellCorners(cell, lo, hi);
#endif
  mc_cellsWalked += 1.0;
#ifdef MC_CROP_REGIONS
  // Cropping regions (clip_regions): the segment split at the cropping
  // planes (at most 6 cuts, 7 pieces, written out), each visible piece to
  // the hook; the first piece also when the segment has zero length.
  float a = t0;
  mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
  if (a < t1) mcCropCellPiece(ray, cell, lo, hi, a, t1, rayMax);
#else
  mcCell(lo, hi, ray.origin + t0 * ray.dir - vec3(cell), (t1 - t0) * ray.dir, t1 - t0, rayMax);
#endif
  bvec3 stepped = lessThanEqual(tNext, vec3(t1 * (1.0 + 1.0e-6) + 1.0e-7));
#ifdef MC_GLOBAL_CELLS
  // the next plane of each stepped axis, its parameter from its index
  vec3 plane = vec3(cell) + mix(vec3(-1.0), vec3(2.0), vec3(greaterThan(ray.dir, vec3(0.0))));
  vec3 direct = mix((plane - ray.origin) / mix(ray.dir, vec3(1.0), vec3(ray.still)), vec3(1.0e30),
                    vec3(ray.still));
  tNext = mix(tNext, direct, vec3(stepped));
#else
  tNext += ray.tDelta * vec3(stepped);
#endif
  t0 = t1;
}
