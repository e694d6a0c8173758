// mipcast piece: whole_ray_end
// fills: RenderToImage::Dec
// mode: augment
// A brick's ray ends where the WHOLE volume's ray ends (a brick of
// mipcast.mappers.bricked_draw and the other bricked or distributed draws:
// u_mc_globalTexMin/Max, the whole volume's point bounds in this brick's
// texture coordinates; rendering to image, with image_terminate).
// VTK's set-up (mcSetRayEnd) makes g_terminatePointMax the UNSIGNED length,
// in steps, from the ray's start g_dataPos (the box entry + g_rayJitter: one
// step without jittering) to the scene depth's point. The single texture
// counts it from its box's entry; a brick from its own. Where opaque geometry
// lies less than a step behind a brick's entry, the brick's length points the
// wrong way and its ray ends up to two steps past the surface; where geometry
// hides the whole box's entry, the single texture draws nothing, while a brick
// of the whole-volume rays (global_phase, not discarded behind the scene)
// kept its sample 0. mcWholeRayEnd: the single texture's length from the whole
// box's entry + jitter, counted from this brick's g_dataPos (signed), so the
// sampled loop keeps the whole ray's samples 0 .. ceil(length) and the cell
// walk ends where the single texture's does; discard where the single texture
// draws nothing, and a cell walk whose end lies before this brick.
#define MC_WHOLE_RAY_END

void mcWholeRayEnd()
{
  float mc_step2 = dot(g_dirStep, g_dirStep);
  vec3 mc_entry = g_dataPos - g_rayJitter;  // this brick's entry
  float mc_near = mcLineThroughBox(mc_entry, g_dirStep, u_mc_globalTexMin, u_mc_globalTexMax).x;
  vec3 mc_wholeEntry = mc_entry + min(mc_near, 0.0) * g_dirStep;
  if (dot(g_terminatePos - mc_wholeEntry, g_dirStep) < 0.0)
  {
    discard;  // opaque geometry hides the whole box's entry: the single texture draws nothing here
  }
  vec3 mc_start = mc_wholeEntry + g_rayJitter;  // the single texture's g_dataPos
  g_terminatePointMax = length(g_terminatePos - mc_start) / sqrt(mc_step2)
                        + dot(mc_start - g_dataPos, g_dirStep) / mc_step2;
#ifndef MC_GLOBAL_PHASE
  if (g_terminatePointMax + dot(g_rayJitter, g_dirStep) / mc_step2 < 0.0)
  {
    discard;  // the cell walk ends before this brick
  }
#endif
}
