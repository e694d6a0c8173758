// mipcast piece: stereo_ray_direction
// fills: ComputeRayDirection::Dec
// mode: replace
// Installed only while an eye of a parallel stereo pair renders
// (mipcast/mappers/stereo.py; perspective eyes have perspective_ray_direction,
// their pixels' lines through the eye's sheared frustum). VTK's stereo
// shears each eye's projection; VTK's own computeRayDirection() still aims
// rays along the mono direction, flattening a volume's parallax to a
// uniform shift. Here rays run along the eye's sheared direction of
// projection, u_mc_eyeDirection (world space).
vec3 computeRayDirection()
{
  return normalize((in_inverseVolumeMatrix[0] * vec4(u_mc_eyeDirection, 0.0)).xyz);
}
