// mipcast piece: sampled_loop
// fills: Shading::Init
// mode: replace
// The one sampled ray loop, shared by every sampled method (MIP, DEMIP, LMIP,
// attenuated MIP, MIDA, both passes of two-pass DEMIP, and any new sampled
// projection). Samples sit where VTK's stock loop puts them: the first one
// step after the box entry (g_dataPos; where the ray_mend piece is
// installed, mended by mcMendRay where VTK's fragment lies off the box),
// then every g_dirStep while the position stays inside the point bounds and
// before the depth-buffer / clipping termination (g_terminatePointMax).
// Sample i is at g_dataPos + i * g_dirStep, not a running sum: summing
// thousands of float steps (dense sampling) drifts by a good fraction of a
// voxel.
//
// Hooks (after vispy's volume.py: one template, a method fills only its
// hooks). A sampled method is ONE hook piece filling Picking::Dec (global
// scope, after VTK's computeColor/computeOpacity and mipcast's mip_globals
// and demip_helpers) that defines:
//   void mcBeginRay(inout int first, inout int count)
//       before the loop: samples first .. count - 1 are marched (on entry 0
//       and this ray's number of samples; a method may narrow them).
//   bool mcSample(float value, int i)
//       at sample i; value is the raw texel value (VTK's normalised scalar:
//       mcNormalised(value), mip_globals). Return false to end the ray before
//       sample i (then count becomes i).
//   void mcEndRay(int count)
//       after the loop(s), count the samples marched: leave the ray's
//       normalised value in mc_rayMax for the colour and readout pieces.
// Optional block skipping, when the hook piece does "#define
// MC_SAMPLE_BLOCKS" (mip_hooks_blocks: block maxima in in_mask;
// minip_hooks_blocks: block minima; their edge u_mc_blockSize cells, the
// volume u_mc_dims points):
//   bool mcBlockSkips(float blockBound)
//       whether a block whose bound (raw, as the samples) is blockBound
//       cannot change the running value; its samples are then jumped over
//       (indices keep their positions; with cropping regions only their
//       visibility is tested, while the ray has no visible sample yet). Not
//       with a global phase.
// Optional second march over the same samples (DEMIP's same-material
// search), run when the hook piece does "#define MC_SECOND_MARCH"; DEMIP's
// second-march hooks are in demip_helpers:
//   bool mcBeginSecondMarch(inout int first, inout int count)
//       after the first march (on entry 0 and its count); false: no march.
//   bool mcSecondSample(float value, int i)   true: sample i is the one, stop.
//   void mcEndSecondMarch(int found)          the index found, -1 if none.
// Clipping (planes, cropping box, slab; mcClipRange): the ray keeps the
// unclipped ray's sample positions and marches only the samples inside the
// kept interval (first > 0 then); a ray with none left draws nothing.
// Cropping regions other than the sub-volume (the clip_regions piece defines
// MC_CROP_REGIONS): both marches skip the samples in hidden regions (the
// hooks never see them; indices i keep their positions), and a ray without
// a visible sample draws nothing.
// Per-sample work is the hooks' only: every lane of a SIMD group runs the
// same loop (llvmpipe runs lanes in lockstep).
// Bricks of a distributed volume (mipcast.distributed): with the
// global_phase piece installed (it defines MC_GLOBAL_PHASE and
// mcGlobalPhase), sample i sits at mc_base + i * g_dirStep where mc_base is
// the WHOLE volume's first sample along this ray, and first .. count - 1
// are the whole volume's samples that lie in this brick: every brick takes
// the single-process sample positions and indices; the values are read by
// mcGlobalSample(i) (the whole-volume ray, interpolated by hand), so they
// are bit for bit the same whatever the split.
#ifdef MC_RAY_MEND
  if (!mcMendRay())  // VTK's set-up from a fragment off the box (ray_mend)
  {
    MC_DRAW_NOTHING(g_fragColor)  // the pixel's line misses the box
  }
#endif
  // a start off the box's entry along its line moves there (mip_globals: mcEntryShift; the box from the start
  // after the jitter, in steps)
  vec2 mc_box = mcLineThroughBox(g_dataPos, g_dirStep, in_texMin[0], in_texMax[0]);
  float mc_jitterSteps = dot(g_rayJitter, g_dirStep) / dot(g_dirStep, g_dirStep);
  float mc_shift = mcEntryShift(mc_box + mc_jitterSteps, length(g_dirStep));
  g_dataPos += mc_shift * g_dirStep;
  g_terminatePointMax -= mc_shift;
  float mc_stepsInBox = mc_box.y - mc_shift;
  vec3 mc_base = g_dataPos;
  int mc_first = 0;
  int mc_count = 1 + int(max(0.0, floor(mc_stepsInBox)));
  mc_count = min(mc_count, int(ceil(max(g_terminatePointMax, 0.0))) + 1);
#ifdef MC_GLOBAL_PHASE
  mcGlobalPhase(mc_stepsInBox, mc_base, mc_first, mc_count);
  // opaque geometry ends the whole ray's samples where it ends the single texture's (whole_ray_end): sample k
  // (at mc_base + k steps) up to ceil of the terminate point's steps from sample 0
  mc_count = min(mc_count, int(ceil(max(g_terminatePointMax - dot(mc_base - g_dataPos, g_dirStep)
                                         / dot(g_dirStep, g_dirStep), 0.0))) + 1);
#endif
#ifdef MC_CLIPPING
  if (u_mc_clipCount > 0)
  {
    float mc_lo = 0.0;
    float mc_hi = float(mc_count);
    mcClipRange(mc_base, g_dirStep, mc_lo, mc_hi);
    // a sample on a plane is kept whatever rounding makes of it: 1e-3 of a step (mipcast.core.clipping.SAMPLE_ON_PLANE)
    mc_first = max(mc_first, int(ceil(clamp(mc_lo - 1.0e-3, 0.0, float(mc_count)))));
    mc_count = min(mc_count, int(floor(clamp(mc_hi + 1.0e-3, -1.0, float(mc_count)))) + 1);
    if (mc_count <= mc_first)
    {
      MC_DRAW_NOTHING(g_fragColor)  // clipped away: nothing of the ray is left
    }
  }
#endif
#ifdef MC_CROP_REGIONS
  {
    // only the samples within the hull of the visible regions (one step of
    // margin each side: the per-sample test below decides)
    float mc_lo = float(mc_first) - 1.0;
    float mc_hi = float(mc_count);
    mcCropVisibleHull(mc_base, g_dirStep, u_mc_cropLow, u_mc_cropHigh, mc_lo, mc_hi);
    if (mc_lo > mc_hi)
    {
      MC_DRAW_NOTHING(g_fragColor)  // the ray crosses hidden cropping regions only
    }
    mc_first = max(mc_first, int(ceil(mc_lo)) - 1);
    mc_count = min(mc_count, int(floor(mc_hi)) + 2);
  }
#endif
  mcBeginRay(mc_first, mc_count);
#ifdef MC_CROP_REGIONS
  bool mc_seen = false;
#endif
#if defined(MC_SAMPLE_BLOCKS) && !defined(MC_GLOBAL_PHASE)
  // the samples in point coordinates (point k of an axis at k); samples
  // before mc_blockEnd lie in the block checked last
  vec3 mc_pointBase = mc_base * u_mc_dims - 0.5;
  vec3 mc_pointStep = g_dirStep * u_mc_dims;
  vec3 mc_lastBlock = floor((u_mc_dims - 2.0) / u_mc_blockSize);
  vec3 mc_stepSign = vec3(greaterThan(mc_pointStep, vec3(0.0)));
  vec3 mc_still = vec3(equal(mc_pointStep, vec3(0.0)));
  vec3 mc_safeStep = mix(mc_pointStep, vec3(1.0), mc_still);
  int mc_blockEnd = mc_first;
#endif
  for (int mc_i = mc_first; mc_i < mc_count; ++mc_i)
  {
#if defined(MC_SAMPLE_BLOCKS) && !defined(MC_GLOBAL_PHASE)
    if (mc_i >= mc_blockEnd)
    {
      // the block of cells holding sample mc_i, and the last sample in its
      // box (where the ray leaves it); jump past them if the block cannot
      // change the running value
      vec3 mc_block = clamp(floor((mc_pointBase + float(mc_i) * mc_pointStep) / u_mc_blockSize), vec3(0.0),
                            mc_lastBlock);
      vec3 mc_toFace = mix(((mc_block + mc_stepSign) * u_mc_blockSize - mc_pointBase) / mc_safeStep, vec3(1.0e30),
                           mc_still);
      float mc_leave = min(min(mc_toFace.x, mc_toFace.y), mc_toFace.z);
      mc_blockEnd = max(mc_i + 1, int(min(floor(mc_leave), float(mc_count))) + 1);
      if (mcBlockSkips(mcRaw(texelFetch(in_mask, ivec3(mc_block), 0).r)))
      {
#ifdef MC_CROP_REGIONS
        // a jumped sample cannot change the value, but a visible one means the ray has one
        for (int mc_j = mc_i; mc_j < mc_blockEnd && !mc_seen; ++mc_j)
        {
          mc_seen = mcCropSampleVisible(mc_base, g_dirStep, mc_j);
        }
#endif
        mc_i = mc_blockEnd - 1;
        continue;
      }
    }
#endif
#ifdef MC_CROP_REGIONS
    if (!mcCropSampleVisible(mc_base, g_dirStep, mc_i))
    {
      continue;  // a hidden cropping region: the sample does not count
    }
    mc_seen = true;
#endif
#ifdef MC_GLOBAL_PHASE
    float mc_global = mcGlobalSample(mc_i);
    if (mc_global < -1.0e29)
    {
      continue;  // a sample of a cell in another brick (never a maximum, never a minimum)
    }
    if (!mcSample(mc_global, mc_i))
#else
    if (!mcSample(texture3D(in_volume[0], mc_base + float(mc_i) * g_dirStep).r, mc_i))
#endif
    {
      mc_count = mc_i;
      break;
    }
  }
#ifdef MC_CROP_REGIONS
  if (!mc_seen)
  {
    MC_DRAW_NOTHING(g_fragColor)  // no sample in a visible cropping region
  }
#endif
#ifdef MC_SECOND_MARCH
  int mc_from = mc_first;
  int mc_to = mc_count;
  if (mcBeginSecondMarch(mc_from, mc_to))
  {
    int mc_found = -1;
    for (int mc_j = mc_from; mc_j < mc_to; ++mc_j)
    {
#ifdef MC_CROP_REGIONS
      if (!mcCropSampleVisible(mc_base, g_dirStep, mc_j))
      {
        continue;
      }
#endif
#ifdef MC_GLOBAL_PHASE
      if (mcSecondSample(mcGlobalSample(mc_j), mc_j))
#else
      if (mcSecondSample(texture3D(in_volume[0], mc_base + float(mc_j) * g_dirStep).r, mc_j))
#endif
      {
        mc_found = mc_j;
        break;
      }
    }
    mcEndSecondMarch(mc_found);
  }
#endif
  mcEndRay(mc_count);
  g_exit = true;
