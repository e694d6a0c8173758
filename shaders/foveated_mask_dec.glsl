// mipcast piece: foveated_mask_dec
// fills: CompositeMask::Dec
// mode: augment
// Content-adaptive foveation (mipcast/core/content_adaptive.py): this
// level's refinement mask, one texel per ray of its grid (bottom row
// first), > 0.5 where the ray is cast. Bound by the foveated mapper.
uniform sampler2D u_mc_fovMask;

// A masked level (content-adaptive density) is drawn over coarser levels:
// a ray it casts is drawn over the picture that lay beneath the volume
// before the frame's first level (u_mc_fovBeneath, RGBA8, the viewport's
// size u_mc_fovViewSize, bottom row first), and a cast ray that draws
// nothing paints that picture (foveated_paint_beneath); u_mc_fovPaintBeneath 0
// (a float readout): neither, such a ray draws nothing. (Those two are
// custom uniforms, which VTK declares.)
uniform sampler2D u_mc_fovBeneath;
