// mipcast piece: ray_mend
// fills: ComputeLighting::Dec
// mode: augment
// Installed only while a face of the volume's box is seen (nearly) edge-on
// (mipcast.core.camera_rays.grazing_sine below mipcast.mappers.mip.EDGE_ON:
// a volume whose direction matrix turns it about the view axis, seen
// head-on). VTK starts each ray at its fragment's rasterised position on the
// box; such a face rasterises, after float rounding, as a sliver a pixel
// wide whose interpolated position lands anywhere along the pixel's line (in
// front of the box, behind the eye) or is NaN with VTK's step and
// termination (llvmpipe): an analytic MIP walked from there drew 56 to 147
// times the data range, a sampled one 0.7 of it. Both ray loops (sampled_loop,
// amip_loop, amip_loop_blocks) call mcMendRay first, which sets such a ray up
// again along the pixel's line. Not installed otherwise: llvmpipe runs a
// branch's body on every lane (a loop's first pass too), and this one cost
// 5-12 % of a frame in views where no ray took it.
#define MC_RAY_MEND

// The line of pixel `pixelCentre` (counted from its buffer's corner) in the
// dataset's coordinates: at NDC depth z its point is (a + z b) / (a.w + z b.w)
// (-1: the near plane, 1: the far plane). From the uniforms alone: VTK's
// interpolated ip_inverseTextureDataAdjusted is NaN on the slivers of
// mcMendRay.
void mcPixelLine(vec2 pixelCentre, out vec4 a, out vec4 b)
{
  vec2 mc_ndc = pixelCentre * 2.0 * in_inverseWindowSize - 1.0;
  vec4 mc_eye = in_inverseProjectionMatrix * vec4(mc_ndc, 0.0, 1.0);
  a = in_inverseVolumeMatrix[0] * (in_inverseModelViewMatrix * mc_eye);
  b = in_inverseVolumeMatrix[0] * (in_inverseModelViewMatrix * in_inverseProjectionMatrix[2]);
}

// Dataset coordinates -> texture coordinates (VTK's ip_inverseTextureDataAdjusted; affine: w kept).
vec4 mcToTexture(vec4 p)
{
  return in_cellToPoint[0] * (in_inverseTextureDatasetMatrix[0] * p);
}

// This fragment's pixel counted from its buffer's corner. VTK's window draws
// count gl_FragCoord from the window's corner, its reduced buffer, mipcast's
// private draws and renders to image from their own (see
// perspective_ray_direction): in a renderer off the window's corner, of the
// two counts the one whose near-plane point lies nearer VTK's line
// (`onLine` + s `dir`, texture coordinates; NaN: the window's count unless
// that puts the pixel before the viewport).
vec2 mcBufferPixel(vec3 onLine, vec3 dir)
{
  if (all(equal(in_windowLowerLeftCorner, vec2(0.0))))
  {
    return gl_FragCoord.xy;
  }
  vec2 mc_offset = gl_FragCoord.xy - in_windowLowerLeftCorner;
  vec4 mc_a;
  vec4 mc_b;
  mcPixelLine(gl_FragCoord.xy, mc_a, mc_b);
  vec4 mc_near = mcToTexture(mc_a - mc_b);
  vec3 mc_ownAcross = mc_near.xyz / mc_near.w - onLine;
  mcPixelLine(mc_offset, mc_a, mc_b);
  mc_near = mcToTexture(mc_a - mc_b);
  vec3 mc_offsetAcross = mc_near.xyz / mc_near.w - onLine;
  mc_ownAcross -= dot(mc_ownAcross, dir) * dir;
  mc_offsetAcross -= dot(mc_offsetAcross, dir) * dir;
  if (!(dot(mc_ownAcross, mc_ownAcross) >= 0.0))
  {
    return any(lessThan(mc_offset, vec2(0.0))) ? gl_FragCoord.xy : mc_offset;
  }
  return dot(mc_offsetAcross, mc_offsetAcross) < dot(mc_ownAcross, mc_ownAcross) ? mc_offset : gl_FragCoord.xy;
}

// Whether texture point p lies in the point bounds (1e-4 of slack; false for NaN).
bool mcInBox(vec3 p)
{
  return all(greaterThanEqual(p, in_texMin[0] - 1.0e-4)) && all(lessThanEqual(p, in_texMax[0] + 1.0e-4));
}

// Whether texture point p lies on the plane of a face that the unit
// direction dir meets at a sine above 0.01 (false for NaN).
bool mcOnSquareFace(vec3 p, vec3 dir)
{
  bvec3 onPlane = lessThanEqual(min(abs(p - in_texMin[0]), abs(p - in_texMax[0])), vec3(1.0e-6));
  return any(bvec3(vec3(onPlane) * vec3(greaterThan(abs(dir), vec3(0.01)))));
}

// VTK sets a ray up from the fragment's rasterised position: its entry
// g_rayOrigin lies where the pixel's line enters the box, or, where the
// camera's near plane cuts the box, on VTK's cap just beyond that plane. On
// a face seen nearly edge-on that position is not to be trusted along the
// line (off the box, a tenth of the box into it along the face, NaN).
// VTK's set-up is kept where its entry lies in the box where the
// line enters it through a face seen at a sine above 0.01 (in texture
// space), and on the cap (an entry in the box while the pixel's near-plane
// point is in it too; a sliver's that lands there is not told from them);
// every other ray is set up again as VTK would have set it up for its
// pixel's line: the direction normalised in dataset space, times the sample
// distance; the entry where the line enters the box; the jitter's fraction
// of a step kept (1 where it was lost); the end where the Terminate::Init
// piece put it (g_terminatePos; NaN: the scene's depth), g_terminatePointMax
// signed from the new start (a brick's whole_ray_end count is not kept).
// False: the pixel's line misses the box (the ray draws nothing: with MSAA,
// the pixels whose centre lies off the box, which VTK draws from the face's
// plane). The comparisons hold for NaN.
bool mcMendRay()
{
  vec3 mc_entry = g_dataPos - g_rayJitter;
  vec3 mc_dir = normalize(g_dirStep);
  bool mc_inBox = mcInBox(mc_entry);
  bool mc_atEntry = abs(mcLineThroughBox(mc_entry, mc_dir, in_texMin[0], in_texMax[0]).x) <= 1.0e-4;
  if (mc_inBox && mc_atEntry && mcOnSquareFace(mc_entry, mc_dir))
  {
    return true;  // where the line enters the box, through a face not seen near edge-on
  }
  vec2 mc_pixel = mcBufferPixel(mc_entry, mc_dir);
  vec4 mc_a;
  vec4 mc_b;
  mcPixelLine(mc_pixel, mc_a, mc_b);
  vec4 mc_aTex = mcToTexture(mc_a);
  vec4 mc_bTex = mcToTexture(mc_b);
  vec3 mc_near = (mc_aTex.xyz - mc_bTex.xyz) / (mc_aTex.w - mc_bTex.w);
  if (mc_inBox && dot(mc_dir, mc_dir) > 0.5 && mcInBox(mc_near))
  {
    return true;  // VTK's near-plane cap
  }
  float mc_jitter = dot(g_rayJitter, g_dirStep) / dot(g_dirStep, g_dirStep);
  mc_jitter = mc_jitter >= 0.0 && mc_jitter <= 1.0 ? mc_jitter : 1.0;
  vec3 mc_far = (mc_aTex.xyz + mc_bTex.xyz) / (mc_aTex.w + mc_bTex.w);
  vec3 mc_span = (mc_a.xyz + mc_b.xyz) / (mc_a.w + mc_b.w) - (mc_a.xyz - mc_b.xyz) / (mc_a.w - mc_b.w);
  g_dirStep = (mc_far - mc_near) * (in_sampleDistance / length(mc_span));  // VTK's: normalised in dataset space
  mc_dir = normalize(g_dirStep);
  vec2 mc_through = mcLineThroughBox(mc_near, mc_dir, in_texMin[0], in_texMax[0]);
  g_rayJitter = mc_jitter * g_dirStep;
  g_rayOrigin = mc_near + max(mc_through.x, 0.0) * mc_dir + g_rayJitter;
  g_dataPos = g_rayOrigin;
  if (!(dot(g_terminatePos, g_terminatePos) >= 0.0))
  {
    float mc_sceneDepth = texture2D(in_depthSampler, mc_pixel * in_inverseWindowSize).x;
    float mc_endDepth = (2.0 * mc_sceneDepth - (gl_DepthRange.near + gl_DepthRange.far)) / gl_DepthRange.diff;
    g_rayTermination = (mc_aTex.xyz + mc_endDepth * mc_bTex.xyz) / (mc_aTex.w + mc_endDepth * mc_bTex.w);
    g_terminatePos = g_rayTermination;
  }
  g_terminatePointMax = dot(g_terminatePos - g_dataPos, g_dirStep) / dot(g_dirStep, g_dirStep);
  return mc_through.y >= max(mc_through.x, 0.0);
}
