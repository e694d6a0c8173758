// mipcast piece: clipping_off
// fills: Clipping::Init
// mode: replace
// VTK's clipping at this tag moves the ray's start (g_rayOrigin, g_dataPos)
// to the clipped entry, which would shift mipcast's samples and cells.
// mipcast clips in its own loops instead (mcClipRange, mip_globals): the
// mapper's clipping planes, its cropping box and its slab reach the shader
// as u_mc_clip0 .. u_mc_clip13 (mipcast/mappers/clip_uniforms.py).
