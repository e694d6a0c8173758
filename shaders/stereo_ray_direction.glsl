// mipcast piece: stereo_ray_direction
// fills: ComputeRayDirection::Dec
// mode: replace
// Installed only while an eye of a stereo pair renders
// (mipcast/mappers/stereo.py). VTK's stereo shears each eye's projection,
// which is the camera moved sideways plus an off-axis frustum; VTK's own
// computeRayDirection() still aims rays from the mono camera position
// (perspective) or along the mono direction (parallel), flattening a
// volume's parallax to a uniform shift. Here rays leave from the eye:
// u_mc_eyePosObj is the eye's centre of projection in the volume's object
// space (perspective), u_mc_eyeDirection the eye's direction of projection
// in world space (parallel, u_mc_eyeParallel = 1).
vec3 computeRayDirection()
{
  if (u_mc_eyeParallel > 0.5)
  {
    return normalize((in_inverseVolumeMatrix[0] * vec4(u_mc_eyeDirection, 0.0)).xyz);
  }
  return normalize(ip_vertexPos.xyz - u_mc_eyePosObj);
}
