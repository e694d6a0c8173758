// mipcast piece: foveated_keep_pass
// fills: CompositeMask::Dec
// mode: augment
// Progressive refinement keeps what it has: the fragment code of a small
// pass (not installed in the ray caster; mipcast.mappers.refine_keep
// compiles it into VTK's full-screen quad template, drawn over the
// viewport after a still frame's levels, blending and depth test off).
// Where the last frame's full-quality disc (eccentricity from its gaze
// u_mc_fovKeptGaze below u_mc_fovKeep) and this frame's (from u_mc_fovGaze
// below u_mc_fovKeepBound) overlap -- the whole last disc for a still frame
// of progressive refinement -- it writes the last frame's picture
// (u_mc_fovKept: the viewport's RGBA8 copy, bottom row first), which is full
// quality there; level 0 skipped a slightly smaller region (foveated_skip's
// u_mc_fovSkip*), so every pixel is either kept or cast.
uniform sampler2D u_mc_fovKept;
uniform vec2 u_mc_fovGaze;
uniform vec2 u_mc_fovKeptGaze;
uniform float u_mc_fovAspect;
uniform float u_mc_fovKeep;
uniform float u_mc_fovKeepBound;
uniform vec2 u_mc_fovSize;  // the viewport's size in pixels

// ``at``: the quad's texture coordinate, 0..1 over the viewport (a pixel
// centre is (i + 0.5) / size, so floor(at * size) is its pixel exactly).
vec4 mcFovKeepPass(vec2 at)
{
  vec2 scale = vec2(u_mc_fovAspect, 1.0);
  if (length((at - u_mc_fovKeptGaze) * scale) >= u_mc_fovKeep || length((at - u_mc_fovGaze) * scale) >= u_mc_fovKeepBound)
  {
    discard;
  }
  return texelFetch(u_mc_fovKept, ivec2(floor(at * u_mc_fovSize)), 0);
}
