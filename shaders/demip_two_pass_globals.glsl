// mipcast piece: demip_two_pass_globals
// fills: Termination::Dec
// mode: augment
// Two-pass DEMIP (mipcast/mappers/demip_two_pass.py): what the first pass (a MIP
// march) hands the second through a float texture, per pixel. Sample k of a
// ray sits at g_dataPos + k * g_dirStep in both passes (same camera, volume
// and sample distance), so two sample indices say everything:
//   mc_firstMax    index of the ray's (first) maximum sample;
//   mc_firstStart  where the second march may start (demip_hooks's level
//                  bookkeeping: no earlier sample can be the same material).
// Encoding in the float (exact: integers below 2^24):
//   -1 - (start * u_mc_indexBase + max)  when the ray has at most
//                                        u_mc_indexBase samples;
//   2 + max (start 0)                    for longer rays;
//   1.0 (the render-to-image clear value): the first pass cast no ray here.
int mc_firstStart;
int mc_firstMax;
bool mc_firstPacked;  // pass 1: the ray was short enough to pack the start index
