// mipcast piece: amip_corners_packed
// fills: Cropping::Dec
// mode: augment
// Analytic MIP on the packed volume (mipcast/mappers/corner_packing.py): texel
// (x, y, z) holds the values at (x, y, z), (x, y+1, z), (x, y, z+1) and
// (x, y+1, z+1) in its four components, so a cell's 8 corners are two
// texelFetch calls instead of eight (same order as amip_corners).
void mcCellCorners(ivec3 cell, out vec4 lo, out vec4 hi)
{
  lo = texelFetch(in_volume[0], cell, 0);
  hi = texelFetch(in_volume[0], cell + ivec3(1, 0, 0), 0);
}
