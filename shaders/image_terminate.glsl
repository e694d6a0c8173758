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
// A brick of a larger volume (the whole_ray_end piece, MC_WHOLE_RAY_END)
// ends its ray where the whole volume's ray ends instead (mcWholeRayEnd; a
// brick of the sampled loop's whole-volume rays is not discarded behind
// opaque geometry: the whole ray takes one sample past the surface, samples
// 0 .. ceil(T) as VTK's loop, and when the surface lies less than a step
// before this brick, that sample is this brick's).
  mcRefuseIfAsked();
  g_terminatePointMax = 0.0;
  vec2 mc_at = gl_FragCoord.xy * in_inverseWindowSize;
  float mc_sceneDepth = texture2D(in_depthSampler, mc_at).x;
#ifndef MC_WHOLE_RAY_END
  if (gl_FragCoord.z >= mc_sceneDepth)
  {
    discard;  // opaque geometry hides the volume here
  }
#endif
  mcSetRayEnd(mc_at, (2.0 * mc_sceneDepth - (gl_DepthRange.near + gl_DepthRange.far))
                     / gl_DepthRange.diff);
#ifdef MC_WHOLE_RAY_END
  mcWholeRayEnd();
#endif
