// mipcast piece: mip_color_packed
// fills: Shading::Exit
// mode: replace
// Colour the ray's maximum exactly as VTK's MIP does: the volume property's
// colour and scalar-opacity transfer functions, premultiplied alpha. For the
// packed four-component volume of analytic MIP (mipcast/mappers/corner_packing.py):
// VTK's independent-component functions, those of component 0.
  g_srcColor = computeColor(vec4(mc_rayMax), computeOpacity(vec4(mc_rayMax), 0), 0);
  g_fragColor.rgb = g_srcColor.rgb * g_srcColor.a;
  g_fragColor.a = g_srcColor.a;
