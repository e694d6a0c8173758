// mipcast piece: perspective_ray_direction
// fills: ComputeRayDirection::Dec
// mode: replace
// Installed for mono perspective frames (stereo frames have
// stereo_ray_direction). VTK aims a perspective ray from the eye at the
// fragment's rasterised position, normalize(ip_vertexPos - eye), both in
// float32. When the eye is inside the volume the fragment is VTK's
// near-plane cap, 0.001 of the clipping range in front of the eye, and the
// float32 rounding of the two points (~1e-6 of their coordinates) turns
// into ~1e-4 of a radian of direction: samples far down the ray move by
// 1e-4 of a cell or more, against a float64 ray through the pixel centre
// (docs/reliability.md, "The eye inside the volume"). Here the direction
// is the pixel's line through the view frustum, the pixel centre
// unprojected onto the near and the far plane: two points the clipping
// range apart, whatever the eye's distance to the volume. The pixel is
// found from the rasterised position, projected (good to ~1e-5 of the
// viewport, far less than half a pixel) and put on the pixel grid of the
// buffer drawn into (in_inverseWindowSize: VTK's reduced buffer and
// mipcast's private draws count gl_FragCoord from their own corner, so
// gl_FragCoord and in_windowLowerLeftCorner do not always agree).
vec3 computeRayDirection()
{
  vec4 mc_clip = in_projectionMatrix * in_modelViewMatrix * inverse(in_inverseVolumeMatrix[0]) *
    vec4(ip_vertexPos.xyz, 1.0);
  vec2 mc_pixel = floor((mc_clip.xy / mc_clip.w + 1.0) * 0.5 / in_inverseWindowSize);
  vec2 mc_ndc = (mc_pixel + 0.5) * 2.0 * in_inverseWindowSize - 1.0;
  vec4 mc_near = in_inverseProjectionMatrix * vec4(mc_ndc, -1.0, 1.0);
  vec4 mc_far = in_inverseProjectionMatrix * vec4(mc_ndc, 1.0, 1.0);
  vec3 mc_eyeDir = mc_far.xyz / mc_far.w - mc_near.xyz / mc_near.w;
  return normalize((in_inverseVolumeMatrix[0] * in_inverseModelViewMatrix * vec4(mc_eyeDir, 0.0)).xyz);
}
