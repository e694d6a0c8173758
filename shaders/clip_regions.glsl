// mipcast piece: clip_regions
// fills: Clipping::Dec
// mode: augment
// Installed instead of clip_active while the mapper crops with region flags
// other than the sub-volume (SetCroppingRegionFlags: Fence, Cross, any of the
// 2^27 values). The six cropping planes cut the volume into 27 regions;
// region (i, j, k) per axis 0 below the first plane, 1 from it up to the
// second, 2 from the second on (VTK's rule) is visible where bit
// i + 3 j + 9 k of u_mc_cropFlags is set. u_mc_cropLow / u_mc_cropHigh are
// the planes in texture coordinates (mipcast/mappers/clip_uniforms.py).
// The sampled loop skips samples in hidden regions; the cell walk (amip_cell)
// splits each cell's segment at the planes and hands only the visible pieces
// to its mcCell hook; both first narrow each ray to the hull of its visible
// pieces (mcCropVisibleHull). Clipping planes and slabs still narrow each ray with
// mcClipRange (MC_CLIPPING). A ray that meets no visible sample (piece) draws
// nothing. Sub-volume cropping and no cropping never carry this code.
#define MC_CLIPPING
#define MC_CROP_REGIONS

// Whether the point p lies in a visible region of the planes low / high
// (one space: texture coordinates, or index space for the cell walk).
bool mcCropRegionVisible(vec3 p, vec3 low, vec3 high)
{
  ivec3 code = ivec3(greaterThanEqual(p, low)) + ivec3(greaterThanEqual(p, high));
  return ((u_mc_cropFlags >> (code.x + 3 * code.y + 9 * code.z)) & 1) != 0;
}

// The sampled loop's test: sample i at base + i * step (texture coordinates) counts. A sample on a
// region's boundary counts when the region on either side of it along the ray is visible (1e-3 of a step:
// mipcast.core.clipping.sample_visible, SAMPLE_ON_PLANE), whatever float rounding makes of it.
bool mcCropSampleVisible(vec3 base, vec3 step, int i)
{
  vec3 p = base + float(i) * step;
  vec3 e = 1.0e-3 * step;
  return mcCropRegionVisible(p - e, u_mc_cropLow, u_mc_cropHigh) || mcCropRegionVisible(p + e, u_mc_cropLow,
                                                                                          u_mc_cropHigh);
}

// The first crossing of a cropping plane by origin + t * dir after t = a,
// or b if none comes before b.
float mcCropNextCut(vec3 origin, vec3 dir, vec3 low, vec3 high, float a, float b)
{
  vec3 still = vec3(equal(dir, vec3(0.0)));
  vec3 safe = mix(dir, vec3(1.0), still);
  vec3 toLow = (low - origin) / safe;
  vec3 toHigh = (high - origin) / safe;
  toLow = mix(toLow, vec3(b), max(still, vec3(lessThanEqual(toLow, vec3(a)))));
  toHigh = mix(toHigh, vec3(b), max(still, vec3(lessThanEqual(toHigh, vec3(a)))));
  vec3 next = min(toLow, toHigh);
  return min(b, min(min(next.x, next.y), next.z));
}

// One piece of the hull search (mcCropVisibleHull): the piece from t to the
// next cropping plane; if visible, first / last grow to hold it.
void mcCropHullPiece(vec3 origin, vec3 dir, vec3 low, vec3 high, inout float t, float b,
                     inout float first, inout float last)
{
  float next = mcCropNextCut(origin, dir, low, high, t, b);
  if (mcCropRegionVisible(origin + (0.5 * (t + next)) * dir, low, high))
  {
    first = min(first, t);
    last = max(last, next);
  }
  t = next;
}

// Narrow [a, b] to the hull of its visible pieces (from the start of the
// first to the end of the last; a > b: none is visible). Once per ray: the
// loops then skip what lies before and after the visible regions.
void mcCropVisibleHull(vec3 origin, vec3 dir, vec3 low, vec3 high, inout float a, inout float b)
{
  float first = 1.0e30;
  float last = -1.0e30;
  float t = a;
  mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  if (t < b) mcCropHullPiece(origin, dir, low, high, t, b, first, last);
  a = first;
  b = last;
}
