// mipcast piece: demip_attenuated_hooks
// fills: Picking::Dec
// mode: augment
// Attenuated MIP in the style of napari (vispy's attenuated_mip), hooks for
// sampled_loop: the largest material m_k (place in the window, 0..1,
// mcMaterial) after attenuation by the material already crossed in front of
// it,
//   best = max_k m_k * exp(-u_mc_attenuation * h * sum_{j<k} m_j),
// h the sample distance in voxels (smallest spacing), so the attenuation is
// per voxel of full material and independent of the sample distance. The
// ray's value is the scalar with that material (floor + best * window); no
// DEMIP term.
float mc_decay;
float mc_crossed;
float mc_best;

void mcBeginRay(inout int first, inout int count)
{
  mcBeginMaterial();
  vec3 spacing = abs(in_cellSpacing[0]);
  mc_decay = u_mc_attenuation * in_sampleDistance / min(min(spacing.x, spacing.y), spacing.z);
  mc_crossed = 0.0;
  mc_best = 0.0;
}

bool mcSample(float value, int i)
{
  float material = mcMaterial(value);
  mc_best = max(mc_best, material * exp(-mc_decay * mc_crossed));
  mc_crossed += material;
  return true;
}

void mcEndRay(int count)
{
  mc_rayMax = u_mc_floor + mc_best * (u_mc_ceiling - u_mc_floor);
  mc_matchIndex = -1;
}
