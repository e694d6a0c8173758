// mipcast piece: foveated_skip_masked
// fills: Base::Init
// mode: augment
// Foveated rendering with content-adaptive ray density: as foveated_skip
// (cast only where the eccentricity lies in [u_mc_fovCastFrom,
// u_mc_fovCastTo)), and only where this level's refinement mask asks for
// a ray (the deciding level's picture changes there, or, inside the
// fovea, shows structure). Elsewhere the coarser levels show through.
// Level 0 also casts in the volume's silhouette band (see foveated_skip).
  mc_paintsNothing = u_mc_fovPaintBeneath > 0.5;  // a cast ray never lets the coarser levels show through
  {
    vec2 mc_fovAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    float mc_fovEcc = length((mc_fovAt - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
    if (mcFovKept(mc_fovAt, mc_fovEcc))  // foveated_band_dec: the last frame's picture is kept here
    {
      discard;
    }
    bool mc_fovBand = mcFovBand(mc_fovAt, mc_fovEcc);  // foveated_band_dec
    if ((mc_fovEcc < u_mc_fovCastFrom || mc_fovEcc >= u_mc_fovCastTo
         || texture2D(u_mc_fovMask, mc_fovAt).r < 0.5) && !mc_fovBand)
    {
      discard;
    }
  }
