// mipcast piece: foveated_keep_pass
// fills: CompositeMask::Dec
// mode: augment
// Progressive refinement keeps what it has: the fragment code of a small
// pass (not installed in the ray caster; mipcast.mappers.refine_keep
// compiles it into VTK's full-screen quad template, drawn over the
// viewport after a still frame's levels, blending and depth test off).
// Inside the kept disc (eccentricity below u_mc_fovKeep, computed as
// foveated_skip computes it) it writes the last frame's picture
// (u_mc_fovKept: the viewport's RGBA8 copy, bottom row first), which is
// full quality there; level 0 skipped a slightly smaller disc
// (foveated_skip's u_mc_fovSkip), so every pixel is either kept or cast.
uniform sampler2D u_mc_fovKept;
uniform vec2 u_mc_fovGaze;
uniform float u_mc_fovAspect;
uniform float u_mc_fovKeep;
uniform vec2 u_mc_fovSize;  // the viewport's size in pixels

// ``at``: the quad's texture coordinate, 0..1 over the viewport (a pixel
// centre is (i + 0.5) / size, so floor(at * size) is its pixel exactly).
vec4 mcFovKeepPass(vec2 at)
{
  float ecc = length((at - u_mc_fovGaze) * vec2(u_mc_fovAspect, 1.0));
  if (ecc >= u_mc_fovKeep)
  {
    discard;
  }
  return texelFetch(u_mc_fovKept, ivec2(floor(at * u_mc_fovSize)), 0);
}
