// mipcast piece: amip_loop
// fills: Shading::Init
// mode: replace
// Analytic MIP: the exact maximum of the trilinear interpolant along the ray.
// The ray is walked cell by cell (3D DDA over voxel planes, in continuous
// index space where point i sits at texture coordinate (i + 0.5) / N). In
// each cell the interpolant along the ray is a cubic in the local parameter;
// it is built exactly from the cell's 8 corners (texelFetch, no filtering),
// and its maximum is the largest of the segment's end values and its values
// at the roots of the derivative (clamped into the segment, so no branch).
// Work that cannot change the answer is skipped, exactly: a block of cells
// whose maximum (coarse level in in_mask, see mipcast/max_blocks.py) is not
// above the running maximum is jumped over, and a cell whose largest corner
// is not above it gets no cubic (trilinear values never exceed the corners).
  vec3 mc_dims = u_mc_dims;
  vec3 mc_dirTex = normalize(g_dirStep);
  vec3 mc_entryTex = g_dataPos - g_rayJitter;
  // Ray length inside the point bounds, and up to the depth-buffer / clipping end.
  vec3 mc_parallel = vec3(equal(mc_dirTex, vec3(0.0)));  // never leaves through these planes
  vec3 mc_exitPlanes = mix(in_texMin[0], in_texMax[0], vec3(greaterThan(mc_dirTex, vec3(0.0))));
  vec3 mc_toPlanes = mix((mc_exitPlanes - mc_entryTex) / mix(mc_dirTex, vec3(1.0), mc_parallel),
                         vec3(1.0e30), mc_parallel);
  float mc_length = max(0.0, min(min(mc_toPlanes.x, mc_toPlanes.y), mc_toPlanes.z));
  mc_length = min(mc_length, g_terminatePointMax * length(g_dirStep) + length(g_rayJitter));
  // Index space: p(t) = mc_origin + t * mc_dir, t in texture-space length.
  vec3 mc_origin = mc_entryTex * mc_dims - 0.5;
  vec3 mc_dir = mc_dirTex * mc_dims;
  vec3 mc_absDir = abs(mc_dir);
  bvec3 mc_still = lessThan(mc_absDir, vec3(1.0e-20));
  vec3 mc_tDelta = mix(1.0 / max(mc_absDir, vec3(1.0e-20)), vec3(1.0e30), vec3(mc_still));
  vec3 mc_nextPlane = mix(floor(mc_origin) + 1.0, ceil(mc_origin) - 1.0, vec3(lessThan(mc_dir, vec3(0.0))));
  vec3 mc_tNext = mix((mc_nextPlane - mc_origin) / mix(mc_dir, vec3(1.0), vec3(mc_still)),
                      vec3(1.0e30), vec3(mc_still));
  ivec3 mc_lastCell = ivec3(mc_dims) - 2;
  int mc_maxCells = int(mc_dims.x + mc_dims.y + mc_dims.z) + 3;
  float mc_blockSize = u_mc_blockSize;
  vec3 mc_dirSign = mix(vec3(-1.0), vec3(1.0), vec3(greaterThan(mc_dir, vec3(0.0))));
  float mc_t0 = 0.0;
  // Start from a lower bound: exact values at a few points of the ray (every
  // u_mc_boundStride voxels), so that skipping works from the first block on.
  // They are values of the interpolant on the ray, so they may stand as the
  // answer too.
  mc_rayMax = -1.0e30;
  float mc_boundStep = u_mc_boundStride / max(length(mc_dir), 1.0e-20);
  int mc_boundCount = int(mc_length / mc_boundStep);
  for (int mc_k = 0; mc_k < mc_boundCount; ++mc_k)
  {
    vec3 mc_p = mc_origin + ((float(mc_k) + 0.5) * mc_boundStep) * mc_dir;
    mc_rayMax = max(mc_rayMax, mcTrilinear(clamp(ivec3(floor(mc_p)), ivec3(0), mc_lastCell), mc_p));
  }
  for (int mc_i = 0; mc_i < mc_maxCells && (mc_i == 0 || mc_t0 < mc_length); ++mc_i)
  {
    float mc_t1 = min(min(min(mc_tNext.x, mc_tNext.y), mc_tNext.z), mc_length);
    vec3 mc_mid = mc_origin + (0.5 * (mc_t0 + mc_t1)) * mc_dir;
    ivec3 mc_cell = clamp(ivec3(floor(mc_mid)), ivec3(0), mc_lastCell);
    ivec3 mc_block = mc_cell / int(mc_blockSize);
    float mc_blockMax = (texelFetch(in_mask, mc_block, 0).r - in_volume_bias[0].r) / in_volume_scale[0].r;
    if (mc_blockMax <= mc_rayMax)
    {
      // Jump to where the ray leaves this block, then restart the DDA there.
      vec3 mc_blockLo = vec3(mc_block) * mc_blockSize;
      vec3 mc_blockHi = min(mc_blockLo + mc_blockSize, mc_dims - 1.0);
      vec3 mc_blockExit = (mix(mc_blockLo, mc_blockHi, vec3(greaterThan(mc_dir, vec3(0.0)))) - mc_origin)
                          / mix(mc_dir, vec3(1.0), vec3(mc_still));
      mc_blockExit = mix(mc_blockExit, vec3(1.0e30), vec3(mc_still));
      mc_t0 = max(mc_t1, min(min(min(mc_blockExit.x, mc_blockExit.y), mc_blockExit.z), mc_length));
      vec3 mc_here = mc_origin + mc_t0 * mc_dir;
      vec3 mc_plane = mix(floor(mc_here) + 1.0, ceil(mc_here) - 1.0, vec3(lessThan(mc_dir, vec3(0.0))));
      mc_tNext = mix(mc_t0 + (mc_plane - mc_here) / mix(mc_dir, vec3(1.0), vec3(mc_still)),
                     vec3(1.0e30), vec3(mc_still));
      continue;
    }
    vec4 mc_lo;
    vec4 mc_hi;
    mcCorners(mc_cell, mc_lo, mc_hi);
    vec4 mc_corners = max(mc_lo, mc_hi);
    if (max(max(mc_corners.x, mc_corners.y), max(mc_corners.z, mc_corners.w)) > mc_rayMax)
    {
      mc_rayMax = max(mc_rayMax, mcCellMaximum(mc_lo, mc_hi,
        mc_origin + mc_t0 * mc_dir - vec3(mc_cell), (mc_t1 - mc_t0) * mc_dir));
    }
    // Step every axis whose plane is reached (ties: edges and corners).
    mc_tNext += mc_tDelta * vec3(lessThanEqual(mc_tNext, vec3(mc_t1 * (1.0 + 1.0e-6) + 1.0e-7)));
    mc_t0 = mc_t1;
  }
  mc_rayMax = mc_rayMax * in_volume_scale[0].r + in_volume_bias[0].r;
  g_exit = true;
