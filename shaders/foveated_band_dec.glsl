// mipcast piece: foveated_band_dec
// fills: DepthPeeling::Dec
// mode: augment
// Foveated rendering: the volume's silhouette band, one rule for every level
// piece (foveated_skip, foveated_skip_masked, foveated_skip_coarse cast
// there; foveated_weight gives it weight 1). Level 0 only (u_mc_fovSilOn):
// where a coarser level's bilinear upsampling would blend a ray that hit
// with one that missed (a darker rim inside the outline: within one ray
// spacing of the coarser level the pixel wants, + 1 pixel; levels above 2
// are counted as 2, SILHOUETTE_LEVEL_CAP), level 0 casts the pixel itself,
// with weight 1, whatever a refinement mask says
// (mipcast.core.foveation.silhouette_band). u_mc_fovSil0..5 are the edges
// of the box's projected outline: n.q + c is the distance inside each,
// along the axes, in viewport heights (q = the pixel, x scaled by the
// aspect). at: the pixel in normalised viewport coordinates; ecc: its
// eccentricity.
bool mcFovBand(vec2 at, float ecc)
{
  if (u_mc_fovSilOn < 0.5)
  {
    return false;
  }
  vec2 q = vec2(at.x * u_mc_fovAspect, at.y);
  float inside = min(min(min(dot(u_mc_fovSil0.xy, q) + u_mc_fovSil0.z,
                             dot(u_mc_fovSil1.xy, q) + u_mc_fovSil1.z),
                         min(dot(u_mc_fovSil2.xy, q) + u_mc_fovSil2.z,
                             dot(u_mc_fovSil3.xy, q) + u_mc_fovSil3.z)),
                     min(dot(u_mc_fovSil4.xy, q) + u_mc_fovSil4.z,
                         dot(u_mc_fovSil5.xy, q) + u_mc_fovSil5.z));
  float lam = clamp(log2(1.0 + u_mc_fovGain * max(ecc - u_mc_fovStart, 0.0)), 0.0, u_mc_fovTop);
  return lam > 0.0 && inside < (exp2(min(ceil(lam), 2.0)) + 1.0) * u_mc_fovSilUnit;
}

// Whether level 0 keeps the last frame's picture at this pixel instead of
// casting (mipcast.mappers.refine_keep): inside the last frame's
// full-quality disc (within u_mc_fovSkip of u_mc_fovSkipGaze) and this
// frame's (within u_mc_fovSkipBound of the gaze); never for other levels
// (their u_mc_fovSkip is -1e30). Every level piece discards there first.
bool mcFovKept(vec2 at, float ecc)
{
  return length((at - u_mc_fovSkipGaze) * vec2(u_mc_fovAspect, 1.0)) < u_mc_fovSkip && ecc < u_mc_fovSkipBound;
}

// The blend weight foveated_weight gave this fragment (a cast ray of a
// masked level that met missing data only paints the picture beneath with
// it: foveated_paint_beneath).
float mc_fovWeight = 1.0;
