// mipcast piece: foveated_weight
// fills: Terminate::Exit
// mode: augment
// Foveated rendering: scale this level's premultiplied colour by its blend
// weight clamp(level + 1 - lam, 0, 1), lam = the level the pixel wants
// (clamp((e - start) / width, 0, top)). Drawn coarsest first with VTK's
// premultiplied "over" blending, the levels then lerp between the two that
// bracket lam (mipcast/foveation.py). The coarsest level has weight 1.
  {
    vec2 mc_fovAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
    float mc_fovEcc = length((mc_fovAt - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
    float mc_fovLambda = clamp((mc_fovEcc - u_mc_fovStart) / u_mc_fovWidth, 0.0, u_mc_fovTop);
    g_fragColor *= clamp(u_mc_fovLevel + 1.0 - mc_fovLambda, 0.0, 1.0);
  }
