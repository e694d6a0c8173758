// mipcast piece: average_hooks
// fills: Picking::Dec
// mode: augment
// Sampled average's hooks for sampled_loop, as VTK's AVERAGE_INTENSITY blend:
// only samples whose value lies in the mapper's AverageIPScalarRange count
// (u_mc_averageLow / u_mc_averageHigh, normalised); the picture is the mean
// of opacity(s) * s over them (s the normalised scalar, mc_rayShade, for
// average_color), the float readout the plain mean of their values
// (mc_rayMax). mc_rayWeight is their number (0: stock draws nothing). The
// grey is s itself (stock's), or with u_mc_shadeRemap (input with missing
// values or a constant volume: mipcast.mappers.projections) s remapped as
// (s - u_mc_shadeLow) * u_mc_shadeScale: the normalisation over the finite
// data range (a constant's range widened by 1 each way).
float mc_rayShade;
float mc_rayWeight;
float mc_raySum;
float mc_rayOpacity;  // sum of the counted samples' opacity (average_brick_readout)
float mc_rayOpShade;  // sum of their opacity * s (average_brick_readout)

void mcBeginRay(inout int first, inout int count)
{
  mc_rayShade = 0.0;
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
    mc_rayShade += mc_opacity * (u_mc_shadeRemap > 0.5 ? (s - u_mc_shadeLow) * u_mc_shadeScale : s);
    mc_rayOpacity += mc_opacity;
    mc_rayOpShade += mc_opacity * s;
    mc_raySum += value;
    mc_rayWeight += 1.0;
  }
  return true;
}

void mcEndRay(int count)
{
  mc_rayShade /= max(mc_rayWeight, 1.0);
  mc_rayMax = mcNormalised(mc_raySum / max(mc_rayWeight, 1.0));
}
