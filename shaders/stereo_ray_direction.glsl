// mipcast piece: stereo_ray_direction
// fills: ComputeRayDirection::Dec
// mode: replace
// VTK's computeRayDirection() with the ray aimed from the eye that renders
// (mipcast/mappers/stereo.py). VTK's stereo shears each eye's projection,
// which is the camera moved sideways plus an off-axis frustum; VTK's own
// function still aims rays from the mono camera position (perspective) or
// along the mono direction (parallel), flattening a volume's parallax to a
// uniform shift. u_mc_eyeShift is the eye's offset from the camera in the
// volume's object space (perspective) or the change of the direction of
// projection in world space (parallel); zero for mono frames, where this is
// VTK's code exactly.
uniform vec3 in_projectionDirection;
vec3 computeRayDirection()
{
  if (u_mc_eyeParallel > 0.5)
  {
    return normalize((in_inverseVolumeMatrix[0] * vec4(in_projectionDirection + u_mc_eyeShift, 0.0)).xyz);
  }
  return normalize(ip_vertexPos.xyz - (in_eyePosObjs[0].xyz + u_mc_eyeShift));
}
