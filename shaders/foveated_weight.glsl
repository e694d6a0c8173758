// mipcast piece: foveated_weight
// fills: Terminate::Exit
// mode: augment
// Foveated rendering: scale this level's premultiplied colour by its blend
// weight clamp(level + 1 - lam, 0, 1), lam = the level the pixel wants.
// Acuity schedule (mipcast/core/foveation.py): the ray spacing 2^lam grows
// linearly with the eccentricity beyond u_mc_fovStart, by u_mc_fovGain per
// viewport height, so lam = clamp(log2(1 + gain * max(e - start, 0)), 0, top).
// Drawn coarsest first with VTK's premultiplied "over" blending, the levels
// then lerp between the two that bracket lam. The coarsest level has weight 1;
// so has level 0 in the volume's silhouette band (foveated_skip).
  {
    vec2 mc_fovAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    float mc_fovEcc = length((mc_fovAt - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
    float mc_fovSpacing = 1.0 + u_mc_fovGain * max(mc_fovEcc - u_mc_fovStart, 0.0);
    float mc_fovLambda = clamp(log2(mc_fovSpacing), 0.0, u_mc_fovTop);
    bool mc_fovBand = mcFovBand(mc_fovAt, mc_fovEcc);  // foveated_band_dec
    mc_fovWeight = mc_fovBand ? 1.0 : clamp(u_mc_fovLevel + 1.0 - mc_fovLambda, 0.0, 1.0);
    g_fragColor *= mc_fovWeight;
  }
