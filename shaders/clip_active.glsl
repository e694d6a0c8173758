// mipcast piece: clip_active
// fills: Clipping::Dec
// mode: augment
// Installed only while the mapper clips (clipping planes, a cropping box or a
// slab): the loops narrow each ray to the kept interval (mcClipRange) only
// then, so rays of an unclipped volume carry no clipping code at all. Moving
// a slab or a plane changes uniforms only; turning clipping on or off
// installs this piece (one compile each way, cached by VTK).
#define MC_CLIPPING
