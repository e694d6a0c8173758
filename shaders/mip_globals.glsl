// mipcast piece: mip_globals
// fills: Base::Dec
// mode: augment
// Global shared by castRay() and finalizeRayCast(): the ray's maximum of the
// normalised scalar (VTK's scale/bias applied).
float mc_rayMax;
