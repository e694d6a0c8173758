// mipcast piece: foveated_skip
// fills: Base::Init
// mode: augment
// Foveated rendering (mipcast/core/foveation.py): one pyramid level per layer.
// This level casts a ray only where it contributes to the picture: where
// the pixel's eccentricity (distance to the gaze in viewport heights,
// u_mc_fovGaze in normalised viewport coordinates) lies in
// [u_mc_fovCastFrom, u_mc_fovCastTo). gl_FragCoord is in this level's own
// (possibly reduced) framebuffer; VTK's window uniforms normalise it.
// Level 0 also casts in the volume's silhouette band, where the coarser
// levels' bilinear upsampling would mix hit and missed rays (a constant
// volume's edge would darken); foveated_weight gives it weight 1 there.
// No ray at all where the frame keeps the last frame's full-quality picture
// (mcFovKept, mipcast.mappers.refine_keep), not even in the band.
  {
    vec2 mc_fovAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    float mc_fovEcc = length((mc_fovAt - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
    bool mc_fovBand = mcFovBand(mc_fovAt, mc_fovEcc);  // foveated_band_dec
    if (mcFovKept(mc_fovAt, mc_fovEcc))  // foveated_band_dec
    {
      discard;
    }
    if ((mc_fovEcc < u_mc_fovCastFrom || mc_fovEcc >= u_mc_fovCastTo) && !mc_fovBand)
    {
      discard;
    }
  }
