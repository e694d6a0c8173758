// mipcast piece: amip_cell
// fills: Shading::Dec
// mode: augment
// Cell-level helpers of analytic MIP (corner fetches, trilinear value, cubic).
// Exact maximum over s in [0, 1] of the trilinear interpolant of one cell
// along u(s) = u0 + s * du (local cell coordinates). lo/hi hold the corner
// values at x = 0 / x = 1, ordered (y,z) = (0,0), (1,0), (0,1), (1,1).
// The interpolant is the cubic d0 + d1 s + d2 s^2 + d3 s^3, built by
// lerping along x (linear in s), then y (quadratic), then z (cubic).
float mcCubic(vec4 d, float s)
{
  return d.x + s * (d.y + s * (d.z + s * d.w));
}

float mcCellMaximum(vec4 lo, vec4 hi, vec3 u0, vec3 du)
{
  vec4 a = lo + (hi - lo) * u0.x;          // x-lerped edges at s = 0
  vec4 b = (hi - lo) * du.x;               // ... and their slope in s
  vec2 p0 = a.yw - a.xz;                   // y-differences (k = 0, 1), linear in s
  vec2 p1 = b.yw - b.xz;
  vec2 g0 = a.xz + p0 * u0.y;              // y-lerped: quadratic g0 + g1 s + g2 s^2
  vec2 g1 = b.xz + p0 * du.y + p1 * u0.y;
  vec2 g2 = p1 * du.y;
  vec3 q = vec3(g0.y - g0.x, g1.y - g1.x, g2.y - g2.x);
  vec4 d = vec4(g0.x + q.x * u0.z,
                g1.x + q.x * du.z + q.y * u0.z,
                g2.x + q.y * du.z + q.z * u0.z,
                q.z * du.z);
  // Roots of d1 + 2 d2 s + 3 d3 s^2 by the cancellation-free formula; a
  // missing or out-of-range root is clamped into [0, 1], which only re-tests
  // a point of the segment (never above the true maximum).
  float qa = 3.0 * d.w;
  float qb = 2.0 * d.z;
  float disc = max(qb * qb - 4.0 * qa * d.y, 0.0);
  float qq = -0.5 * (qb + (qb < 0.0 ? -1.0 : 1.0) * sqrt(disc));
  float r1 = abs(qa) > 1.0e-20 ? qq / qa : 0.0;
  float r2 = abs(qq) > 1.0e-20 ? d.y / qq : 0.0;
  float best = max(d.x, d.x + d.y + d.z + d.w);
  best = max(best, mcCubic(d, clamp(r1, 0.0, 1.0)));
  return max(best, mcCubic(d, clamp(r2, 0.0, 1.0)));
}

// The 8 corner values of cell c (raw texel values, no filtering).
void mcCorners(ivec3 c, out vec4 lo, out vec4 hi)
{
  lo = vec4(texelFetch(in_volume[0], c, 0).r,
            texelFetch(in_volume[0], c + ivec3(0, 1, 0), 0).r,
            texelFetch(in_volume[0], c + ivec3(0, 0, 1), 0).r,
            texelFetch(in_volume[0], c + ivec3(0, 1, 1), 0).r);
  hi = vec4(texelFetch(in_volume[0], c + ivec3(1, 0, 0), 0).r,
            texelFetch(in_volume[0], c + ivec3(1, 1, 0), 0).r,
            texelFetch(in_volume[0], c + ivec3(1, 0, 1), 0).r,
            texelFetch(in_volume[0], c + ivec3(1, 1, 1), 0).r);
}

// The trilinear interpolant at index-space point p inside cell c, computed
// from the corners in full float precision (the GPU filter is not used).
float mcTrilinear(ivec3 c, vec3 p)
{
  vec4 lo;
  vec4 hi;
  mcCorners(c, lo, hi);
  vec3 u = p - vec3(c);
  vec4 x = mix(lo, hi, u.x);
  vec2 y = mix(x.xz, x.yw, u.y);
  return mix(y.x, y.y, u.z);
}
