// mipcast piece: foveated_skip_coarse
// fills: Base::Init
// mode: augment
// Foveated rendering with content-adaptive ray density, the mask built on
// the GPU: as foveated_skip (cast only where the eccentricity lies in
// [u_mc_fovCastFrom, u_mc_fovCastTo)), and only where mcFovRefine
// (foveated_coarse_dec) asks for a ray, from the deciding level's picture
// read here as a texture -- no readback to the CPU. The ray's index in
// this level's grid is the texel a nearest-filtered mask of the grid's
// size would give; whether it lies in the fovea comes from the CPU's
// float64 spans (mcFovInFovea), which depend on the gaze, not on the
// picture. Elsewhere the coarser levels show through.
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
    if (!mc_fovBand)
    {
      if (mc_fovEcc < u_mc_fovCastFrom || mc_fovEcc >= u_mc_fovCastTo)
      {
        discard;
      }
      int mc_fovColumn = clamp(int(floor(mc_fovAt.x * float(u_mc_fovLevelW))), 0, u_mc_fovLevelW - 1);
      int mc_fovRowUp = clamp(int(floor(mc_fovAt.y * float(u_mc_fovLevelH))), 0, u_mc_fovLevelH - 1);
      int mc_fovRow = u_mc_fovLevelH - 1 - mc_fovRowUp;
      if (!mcFovRefine(mc_fovColumn, mc_fovRow, mcFovInFovea(mc_fovColumn, mc_fovRow)))
      {
        discard;
      }
    }
  }
