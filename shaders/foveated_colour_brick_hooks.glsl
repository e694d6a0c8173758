// mipcast piece: foveated_colour_brick_hooks
// fills: Picking::Dec
// mode: augment
// A foveated DEMIP level whose volume lies beyond the GPU's 3D texture limit
// (mipcast.mappers.bricked_foveated): DEMIP was composited over the bricks
// first on this level's ray grid (mipcast.mappers.bricked_demip: the MAX of
// the bricks' maxima, the MIN of their whole-ray indices of the first
// same-material sample, depth, Eq. 1 and the sphere on the CPU). Its rays
// arrive as two nearest-filtered float textures of the level's grid (bottom
// row first): the maximum (VTK's normalised scalar of the level's volume,
// -1e30 where no brick had a sample; what the float readout writes) and the
// premultiplied DEMIP colour, which foveated_brick_color writes as the
// ray's colour. Otherwise as foveated_brick_hooks: no sample is marched
// (the level's volume is a 2 x 2 x 2 box of the same bounds), and the
// level's cast range, mask, silhouette band and blend weight are its own
// pieces, applied to the composited colour.
uniform sampler2D u_mc_fovValues;
uniform sampler2D u_mc_fovColours;

void mcBeginRay(inout int first, inout int count)
{
  count = first;  // nothing to march: the value and colour are the bricks'
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
  if (mc_rayMax < -1.0e29 && u_mc_fovNoValueDiscard > 0.5)
  {
    discard;
  }
}
