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
    // the volume's silhouette band (level 0 only, u_mc_fovSilOn): where a coarser level's
    // bilinear upsampling would blend a ray that hit with one that missed (a darker rim inside
    // the outline: within one ray spacing of the coarser level the pixel wants, + 1 pixel;
    // levels above 2 are counted as 2, SILHOUETTE_LEVEL_CAP), level 0 casts the pixel itself,
    // with weight 1 (mipcast.core.foveation.silhouette_band).
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
    g_fragColor *= mc_fovBand ? 1.0 : clamp(u_mc_fovLevel + 1.0 - mc_fovLambda, 0.0, 1.0);
  }
