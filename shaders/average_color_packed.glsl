// mipcast piece: average_color_packed
// fills: Shading::Exit
// mode: replace
// average_color for the packed four-component volume of the analytic
// average (mipcast/mappers/corner_packing.py): VTK's independent-component
// transfer functions, those of component 0, as mip_color_packed.
  if (mc_rayWeight <= 0.0)
  {
    discard;
  }
  g_srcColor = computeColor(MC_COLOR_AT(mc_rayMax), computeOpacity(MC_OPACITY_AT(mc_rayMax), 0), 0);  // (mip_globals)
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
