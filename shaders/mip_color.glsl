// mipcast piece: mip_color
// fills: Shading::Exit
// mode: replace
// Colour the ray's maximum as VTK's MIP does: the volume property's colour
// and scalar-opacity transfer functions, premultiplied alpha; read from
// VTK's tables where they hold the value (mcAtTable: VTK's own lookup is half
// a table step off).
  g_srcColor = computeColor(MC_COLOR_AT(mc_rayMax), computeOpacity(MC_OPACITY_AT(mc_rayMax)));  // (mip_globals)
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
