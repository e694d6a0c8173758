// mipcast piece: demip_brick_fetch
// fills: Terminate::Init
// mode: replace
// Distributed DEMIP, phase 2 on one brick (mipcast/mappers/demip_brick.py):
// read the WHOLE volume's per-pixel maximum, reduced over the MPI ranks in
// phase 1, from the float texture the mapper shares as in_depthSampler (in
// this brick's normalised scalar; above 1e29 where no rank's ray met data).
// VTK's code at this tag reads in_depthSampler as the scene depth, so it is
// replaced; the phase renders to image only (float readout), whose
// lower-left pixel is gl_FragCoord's origin. Also does the refusal piece's
// job (this tag takes one piece); ray set-up as mcSetRayEnd (mip_globals).
// The texture's alpha is the scene depth (mipcast.mappers.demip_brick.upload_pixels;
// 1, the far plane, where the texture has fewer channels): with the
// whole_ray_end piece (a brick rendering to image) the ray ends at opaque
// geometry where the whole volume's ray ends, as image_terminate's.
  mcRefuseIfAsked();
  vec2 mc_at = gl_FragCoord.xy * in_inverseWindowSize;
  vec4 mc_fetched = texture2D(in_depthSampler, mc_at);
  mc_globalMax = mc_fetched.r;
  mcSetSceneRayEnd(mc_at, mc_fetched.a);
#ifdef MC_WHOLE_RAY_END
  mcWholeRayEnd();
#endif
