// mipcast piece: no_stock_sample
// fills: Shading::Impl
// mode: replace
// The stock per-sample body is not used: mipcast's loop in Shading::Init has
// already marched the whole ray and set g_exit.
