// mipcast piece: average_color
// fills: Shading::Exit
// mode: replace
// Colour the ray's average as MIP colours its maximum (mip_color): the
// volume property's colour and scalar-opacity transfer functions at the
// mean (mc_rayMax, the normalised value the float readout reports),
// premultiplied alpha; so the window, colour maps and log scales apply
// (VTK's own AVERAGE_INTENSITY blend ignores them and draws a grey of the
// opacity-weighted mean normalised over the data range). A ray with no
// sample in the average's scalar range (or no finite data) draws nothing,
// as in stock.
  if (mc_rayWeight <= 0.0)
  {
    discard;
  }
  g_srcColor = computeColor(MC_COLOR_AT(mc_rayMax), computeOpacity(MC_OPACITY_AT(mc_rayMax)));  // (mip_globals)
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
