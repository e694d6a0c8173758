// mipcast piece: demip_mida_color
// fills: Shading::Exit
// mode: replace
// MIDA's composited colour (demip_mida_hooks), premultiplied, is the pixel.
  g_fragColor = clamp(mc_composite, 0.0, 1.0);
