// mipcast piece: foveated_skip_coarse
// fills: Base::Init
// mode: augment
// Foveated rendering with content-adaptive ray density, the mask built on
// the GPU: as foveated_skip (cast only where the eccentricity lies in
// [u_mc_fovCastFrom, u_mc_fovCastTo)), and only where mcFovRefine
// (foveated_coarse_dec) asks for a ray, from the coarsest level's picture
// read here as a texture -- no readback to the CPU. The ray's index in
// this level's grid is the texel a nearest-filtered mask of the grid's
// size would give; whether it lies in the fovea comes from the CPU's
// float64 spans (mcFovInFovea), which depend on the gaze, not on the
// picture. Elsewhere the coarser levels show through.
// Level 0 also casts in the volume's silhouette band (see foveated_skip).
  {
    vec2 mc_fovAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    float mc_fovEcc = length((mc_fovAt - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
    // the volume's silhouette band (level 0 only, u_mc_fovSilOn): where a coarser level's
    // bilinear upsampling would blend a ray that hit with one that missed (a darker rim inside
    // the outline: within one ray spacing of the coarser level the pixel wants, + 1 pixel;
    // levels above 2 are counted as 2, SILHOUETTE_LEVEL_CAP), level 0 casts the pixel itself,
    // with weight 1 (mipcast.core.foveation.silhouette_band), whatever the refinement mask
    // says -- as foveated_skip_masked does on the CPU mask path.
    // u_mc_fovSil0..5 are the edges of the box's projected outline: n.q + c is the distance
    // inside each, along the axes, in viewport heights (q = the pixel, x scaled by the aspect).
    bool mc_fovBand = false;
    if (u_mc_fovSilOn > 0.5)
    {
      vec2 mc_fovQ = vec2(mc_fovAt.x * u_mc_fovAspect, mc_fovAt.y);
      float mc_fovIn = min(min(min(dot(u_mc_fovSil0.xy, mc_fovQ) + u_mc_fovSil0.z,
                                   dot(u_mc_fovSil1.xy, mc_fovQ) + u_mc_fovSil1.z),
                               min(dot(u_mc_fovSil2.xy, mc_fovQ) + u_mc_fovSil2.z,
                                   dot(u_mc_fovSil3.xy, mc_fovQ) + u_mc_fovSil3.z)),
                           min(dot(u_mc_fovSil4.xy, mc_fovQ) + u_mc_fovSil4.z,
                               dot(u_mc_fovSil5.xy, mc_fovQ) + u_mc_fovSil5.z));
      float mc_fovLam = clamp(log2(1.0 + u_mc_fovGain * max(mc_fovEcc - u_mc_fovStart, 0.0)), 0.0, u_mc_fovTop);
      mc_fovBand = mc_fovLam > 0.0 && mc_fovIn < (exp2(min(ceil(mc_fovLam), 2.0)) + 1.0) * u_mc_fovSilUnit;
    }
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
