// mipcast piece: foveated_mask_dec
// fills: CompositeMask::Dec
// mode: augment
// Content-adaptive foveation (mipcast/core/content_adaptive.py): this
// level's refinement mask, one texel per ray of its grid (bottom row
// first), > 0.5 where the ray is cast. Bound by the foveated mapper.
uniform sampler2D u_mc_fovMask;
