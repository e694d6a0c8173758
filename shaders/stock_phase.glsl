// mipcast piece: stock_phase
// fills: DepthPass::Init
// mode: augment
// VTK's own GPU MIP / MinIP (the "stock" methods) drawing one rank's piece of a
// volume in a parallel ParaView render view (plugin/representation, with the
// stock_depth_composite piece): the piece takes the WHOLE volume's sample
// positions along each ray, not its own. VTK's initializeRayCast() starts the
// ray at this piece's entry (the rasterised box face, g_dataPos - g_rayJitter in
// the piece's texture coordinates) plus the jitter (one step without jittering)
// and its loop takes a sample, advances by g_dirStep and stops past the piece's
// exit or after g_terminatePointMax steps (opaque geometry). Here, after all
// that and before the loop: the whole volume's box in this piece's texture
// coordinates (u_mc_globalTexMin, u_mc_globalTexMax: the whole volume's first
// and last points, mipcast.mappers.brick_rays.global_texture_box) gives the
// whole volume's entry along the same ray (mc_wholeIn steps before this
// entry, <= 0), so its samples sit at mc_wholeIn + jitter + m steps, m >= 0,
// exactly as VTK's loop puts them for the whole volume; the ray starts at the
// first of them at or after this piece's entry (MC_PHASE_SLACK of a step
// before it too: a sample on the face shared with the neighbour piece is
// taken by both rather than by neither, its value read on the face). The
// termination point is counted from the new start (signed: geometry before
// the start leaves no sample). VTK's loop always takes its first sample: when
// that sample lies past this piece's exit (the ray crosses the piece between
// two of the whole volume's samples) the ray takes none (g_exit), unless it
// is the whole volume's first sample and past the whole volume's exit too,
// which VTK's loop over the whole volume takes as well. The end of the ray
// stays VTK's (the last sample not past the piece's exit): the pieces share
// a layer of points, so every whole-volume sample lies in some piece.
// The camera inside the volume (the near plane cuts the whole box): VTK
// starts the whole volume's rays at its near-plane cap where they cross it
// beyond the box's entry, so the samples count from there (u_mc_capTex: the
// cap n . p = w in this piece's texture coordinates,
// mipcast.core.camera_rays.near_cap and texture_plane; n = 0: none), also
// when the cap lies beyond this piece's entry (a piece VTK did not cap).
// Installed on more than one rank only: one rank draws VTK's own shader.
#define MC_PHASE_SLACK 1.0e-3
  {
    vec3 mc_entry = g_dataPos - g_rayJitter;
    float mc_step2 = dot(g_dirStep, g_dirStep);
    bvec3 mc_up = greaterThan(g_dirStep, vec3(0.0));
    bvec3 mc_flat = equal(g_dirStep, vec3(0.0));
    vec3 mc_near = (mix(u_mc_globalTexMax, u_mc_globalTexMin, vec3(mc_up)) - mc_entry)
                   / mix(g_dirStep, vec3(1.0), vec3(mc_flat));
    mc_near = mix(mc_near, vec3(-1.0e30), vec3(mc_flat));
    float mc_capAlong = dot(u_mc_capTex.xyz, g_dirStep);
    float mc_capIn = mc_capAlong > 0.0 ? (u_mc_capTex.w - dot(u_mc_capTex.xyz, mc_entry)) / mc_capAlong : -1.0e30;
    float mc_wholeIn = max(min(max(max(mc_near.x, mc_near.y), mc_near.z), 0.0), mc_capIn);
    float mc_first = mc_wholeIn + dot(g_rayJitter, g_dirStep) / mc_step2;
    float mc_skip = max(0.0, ceil(-mc_first - MC_PHASE_SLACK));
    g_dataPos = mc_entry + (mc_first + mc_skip) * g_dirStep;
    g_terminatePointMax = dot(g_terminatePos - g_dataPos, g_dirStep) / mc_step2;
    bool mc_past = any(greaterThan(max(g_dirStep, vec3(0.0)) * (g_dataPos - in_texMax[0]), vec3(0.0))) ||
                   any(greaterThan(min(g_dirStep, vec3(0.0)) * (g_dataPos - in_texMin[0]), vec3(0.0)));
    bool mc_pastWhole = any(greaterThan(max(g_dirStep, vec3(0.0)) * (g_dataPos - u_mc_globalTexMax), vec3(0.0))) ||
                        any(greaterThan(min(g_dirStep, vec3(0.0)) * (g_dataPos - u_mc_globalTexMin), vec3(0.0)));
    if ((mc_past && (mc_skip > 0.5 || !mc_pastWhole)) || g_terminatePointMax <= -1.0)
    {
      g_exit = true;
    }
  }
