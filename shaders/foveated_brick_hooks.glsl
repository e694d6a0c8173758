// mipcast piece: foveated_brick_hooks
// fills: Picking::Dec
// mode: augment
// A foveated level whose volume lies beyond the GPU's 3D texture limit
// (mipcast.mappers.bricked_foveated): its rays' values were composited over
// the bricks first (the maximum of the bricks' float readouts on this
// level's ray grid, whole-volume rays), and arrive here as a float texture
// of the level's grid (bottom row first, nearest filtered), the value
// VTK's normalised scalar of the level's volume, -1e30 where no brick had a
// sample. No sample is marched (the level's own volume is a 2 x 2 x 2 box
// of the same bounds and scalar range, drawn only to raster the same
// fragments); the colour, the level's cast range, mask, silhouette band
// and blend weight are the level's own pieces, as for a volume in one
// texture. The box is drawn without the user's cropping (the bricks
// honoured it, and with no sample marched the loop would discard every
// ray). A ray without a value (it met missing data, cropped regions or
// clipped space only; the outline rays no brick samples got their sample
// on the CPU) draws nothing, as the single texture's ray does (discarded,
// or in a masked level painting what lies beneath: foveated_paint_beneath):
// the value box holds no missing values, so the level's missing piece is
// not installed to say it. A DEMIP level's composited premultiplied colours arrive
// the same way in u_mc_fovColours (bricked_demip's depth, Eq. 1 and sphere
// on the CPU), which foveated_brick_color writes as the ray's colour; the
// other layers' levels leave it unused.
uniform sampler2D u_mc_fovValues;
uniform sampler2D u_mc_fovColours;

void mcBeginRay(inout int first, inout int count)
{
  count = first;  // nothing to march: the value is the bricks'
  mc_rayMax = -1.0e30;
}

bool mcSample(float value, int i)
{
  return false;
}

void mcEndRay(int count)
{
  vec2 mc_fovValueAt = (gl_FragCoord.xy - in_windowLowerLeftCorner) * in_inverseWindowSize;
  mc_rayMax = texture2D(u_mc_fovValues, mc_fovValueAt).r;
  if (mc_rayMax < -1.0e29)
  {
    mcDrawNothing();  // (mip_globals)
  }
}
