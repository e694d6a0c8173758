// mipcast piece: average_hooks
// fills: Picking::Dec
// mode: augment
// Sampled average's hooks for sampled_loop: only samples whose value lies in
// the mapper's AverageIPScalarRange count (u_mc_averageLow /
// u_mc_averageHigh, normalised), as in VTK's AVERAGE_INTENSITY blend; the
// ray's value (mc_rayMax, coloured by average_color, and the float readout)
// is the plain mean of their values. mc_rayWeight is their number (0: nothing
// is drawn). mc_rayOpacity and mc_rayOpShade sum the counted samples' opacity
// and opacity * s (s the normalised scalar): stock's grey, which
// average_brick_readout writes for VTK's own average drawn over MPI ranks.
float mc_rayWeight;
float mc_raySum;
float mc_rayOpacity;  // sum of the counted samples' opacity (average_brick_readout)
float mc_rayOpShade;  // sum of their opacity * s (average_brick_readout)

void mcBeginRay(inout int first, inout int count)
{
  mc_rayWeight = 0.0;
  mc_raySum = 0.0;
  mc_rayOpacity = 0.0;
  mc_rayOpShade = 0.0;
}

bool mcSample(float value, int i)
{
  float s = mcNormalised(value);
  if (u_mc_averageLow <= s && s <= u_mc_averageHigh)
  {
    float mc_opacity = computeOpacity(vec4(s));
    mc_rayOpacity += mc_opacity;
    mc_rayOpShade += mc_opacity * s;
    mc_raySum += value;
    mc_rayWeight += 1.0;
  }
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_raySum / max(mc_rayWeight, 1.0));
}
