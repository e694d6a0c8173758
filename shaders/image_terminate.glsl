// mipcast piece: image_terminate
// fills: Terminate::Init
// mode: replace
// For renders to image (float readout, DEMIP's first pass): VTK's own ray
// set-up at this tag (end rays at opaque geometry through the scene depth
// in in_depthSampler), with one fix. The image buffer's lower-left pixel is
// the viewport's, while VTK's window uniforms still carry the viewport's
// offset in the window, so in a renderer that does not start at the
// window's corner VTK would read the scene depth of other pixels. Pixel
// coordinates are therefore taken from gl_FragCoord alone (VTK's code is
// identical when the offset is 0). Also does the refusal piece's job (this
// tag takes one piece); the ray set-up is mcSetRayEnd (mip_globals).
  mcRefuseIfAsked();
  g_terminatePointMax = 0.0;
  vec2 mc_at = gl_FragCoord.xy * in_inverseWindowSize;
  float mc_sceneDepth = texture2D(in_depthSampler, mc_at).x;
  if (gl_FragCoord.z >= mc_sceneDepth)
  {
    discard;  // opaque geometry hides the volume here
  }
  mcSetRayEnd(mc_at, (2.0 * mc_sceneDepth - (gl_DepthRange.near + gl_DepthRange.far))
                     / gl_DepthRange.diff);
