// mipcast piece: global_phase
// fills: BinaryMask::Dec
// mode: augment
// One brick of a distributed volume (mipcast.distributed): the sampled loop
// takes the WHOLE volume's sample positions, not the brick's. The whole
// volume's point bounds reach the shader in this brick's texture
// coordinates (u_mc_globalTexMin, u_mc_globalTexMax). As in VTK's loop
// for the whole volume, sample k sits at the whole box's entry + (1 + k)
// steps, for k = 0 .. floor(steps from the first sample to the box's exit);
// this brick marches those k whose position lies in its own point bounds
// (t in [-1, stepsInBox] steps from g_dataPos, a brick's entry being one step
// before g_dataPos), widened by MC_FACE_TOLERANCE steps so that a sample on a
// face two bricks share is taken by at least one of them (a position up to
// that far outside reads the face's value: the texture clamps to its edge).
#define MC_GLOBAL_PHASE
#define MC_FACE_TOLERANCE 1.0e-4

void mcGlobalPhase(float stepsInBox, inout vec3 base, inout int first, inout int count)
{
  bvec3 mc_up = greaterThan(g_dirStep, vec3(0.0));
  vec3 mc_in = (mix(u_mc_globalTexMax, u_mc_globalTexMin, vec3(mc_up)) - g_dataPos) / g_dirStep;
  vec3 mc_out = (mix(u_mc_globalTexMin, u_mc_globalTexMax, vec3(mc_up)) - g_dataPos) / g_dirStep;
  mc_in = mix(mc_in, vec3(-1.0e30), vec3(equal(g_dirStep, vec3(0.0))));
  mc_out = mix(mc_out, vec3(1.0e30), vec3(equal(g_dirStep, vec3(0.0))));
  float mc_g0 = max(max(mc_in.x, mc_in.y), mc_in.z) + 1.0;  // whole volume's sample 0
  float mc_gOut = min(min(mc_out.x, mc_out.y), mc_out.z);
  int mc_last = int(floor(max(mc_gOut - mc_g0, 0.0)));    // as VTK's count for the whole box
  float mc_hi = min(stepsInBox, ceil(max(g_terminatePointMax, 0.0)));
  base = g_dataPos + mc_g0 * g_dirStep;
  first = max(0, int(ceil(-1.0 - MC_FACE_TOLERANCE - mc_g0)));
  count = min(mc_last, int(floor(mc_hi + MC_FACE_TOLERANCE - mc_g0))) + 1;
  if (mc_g0 > mc_gOut)
  {
    // A grazing ray shorter than one step: VTK still takes sample 0, past the
    // whole box, where the texture reads the value at the nearest point of
    // the box. The brick holding that point takes it.
    vec3 mc_near = clamp(base, u_mc_globalTexMin, u_mc_globalTexMax);
    vec3 mc_slack = vec3(MC_FACE_TOLERANCE) * abs(g_dirStep);
    bool mc_mine = all(greaterThanEqual(mc_near, in_texMin[0] - mc_slack)) &&
                   all(lessThanEqual(mc_near, in_texMax[0] + mc_slack));
    first = 0;
    count = mc_mine ? 1 : 0;
  }
}
