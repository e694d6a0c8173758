// mipcast piece: mip_color
// fills: Shading::Exit
// mode: replace
// Colour the ray's maximum exactly as VTK's MIP does: the volume property's
// colour and scalar-opacity transfer functions, premultiplied alpha.
  g_srcColor = computeColor(vec4(mc_rayMax), computeOpacity(vec4(mc_rayMax)));
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
