// mipcast piece: average_color
// fills: Shading::Exit
// mode: replace
// Colour the ray's average as VTK's AVERAGE_INTENSITY blend does: an opaque
// grey of the (opacity-weighted, for the sampled average) mean normalised
// scalar, clamped to [0, 1]; the colour transfer function is not used. A ray
// with no sample in the average's scalar range draws nothing, as in stock.
  if (mc_rayWeight <= 0.0)
  {
    discard;
  }
  g_fragColor = vec4(vec3(clamp(mc_rayShade, 0.0, 1.0)), 1.0);
