// mipcast piece: perspective_ray_direction
// fills: ComputeRayDirection::Dec
// mode: replace
// Installed for perspective frames, mono or an eye of a stereo pair (whose
// sheared frustum's pixel lines leave from that eye; parallel stereo eyes
// have stereo_ray_direction). VTK aims a perspective ray from the eye at the
// fragment's rasterised position, normalize(ip_vertexPos - eye), both in
// float32. When the eye is inside the volume the fragment is VTK's
// near-plane cap, 0.001 of the clipping range in front of the eye, and the
// float32 rounding of the two points (~1e-6 of their coordinates) turns
// into ~1e-4 of a radian of direction: samples far down the ray move by
// 1e-4 of a cell or more, against a float64 ray through the pixel centre
// (docs/reliability.md, "The eye inside the volume"). Here the direction
// is the pixel's line through the view frustum, the pixel centre
// unprojected onto the near and the far plane: two points the clipping
// range apart, whatever the eye's distance to the volume. VTK's reduced
// buffer and mipcast's private draws count gl_FragCoord from their own
// corner, VTK's window draws from the window's: in a renderer off the
// window's corner (in_windowLowerLeftCorner not 0) the pixel is the
// candidate whose line VTK's own direction is closest to (they lie many
// pixels apart: in_windowLowerLeftCorner).
vec3 mcPixelLine(vec2 pixelCentre)
{
  vec2 mc_ndc = pixelCentre * 2.0 * in_inverseWindowSize - 1.0;
  vec4 mc_near = in_inverseProjectionMatrix * vec4(mc_ndc, -1.0, 1.0);
  vec4 mc_far = in_inverseProjectionMatrix * vec4(mc_ndc, 1.0, 1.0);
  vec3 mc_eyeDir = mc_far.xyz / mc_far.w - mc_near.xyz / mc_near.w;
  return normalize((in_inverseVolumeMatrix[0] * (in_inverseModelViewMatrix * vec4(mc_eyeDir, 0.0))).xyz);
}

vec3 computeRayDirection()
{
  vec3 mc_dir = mcPixelLine(gl_FragCoord.xy);
  if (any(notEqual(in_windowLowerLeftCorner, vec2(0.0))))
  {
    vec3 mc_offset = mcPixelLine(gl_FragCoord.xy - in_windowLowerLeftCorner);
    vec4 mc_eye = in_inverseVolumeMatrix[0] * (in_inverseModelViewMatrix * vec4(0.0, 0.0, 0.0, 1.0));
    vec3 mc_vtk = normalize(ip_vertexPos.xyz - mc_eye.xyz / mc_eye.w);  // VTK's own direction
    mc_dir = dot(mc_offset, mc_vtk) > dot(mc_dir, mc_vtk) ? mc_offset : mc_dir;
  }
  return mc_dir;
}
