// mipcast piece: amip_corners
// fills: Cropping::Dec
// mode: augment
// Analytic MIP: a cell's 8 corner values, one texelFetch each (exact: no
// filtering). lo holds the corners at x = 0, hi those at x = 1, ordered
// (y,z) = (0,0), (1,0), (0,1), (1,1).
void mcCellCorners(ivec3 cell, out vec4 lo, out vec4 hi)
{
  lo = vec4(texelFetch(in_volume[0], cell, 0).r,
            texelFetch(in_volume[0], cell + ivec3(0, 1, 0), 0).r,
            texelFetch(in_volume[0], cell + ivec3(0, 0, 1), 0).r,
            texelFetch(in_volume[0], cell + ivec3(0, 1, 1), 0).r);
  hi = vec4(texelFetch(in_volume[0], cell + ivec3(1, 0, 0), 0).r,
            texelFetch(in_volume[0], cell + ivec3(1, 1, 0), 0).r,
            texelFetch(in_volume[0], cell + ivec3(1, 0, 1), 0).r,
            texelFetch(in_volume[0], cell + ivec3(1, 1, 1), 0).r);
}
