// mipcast piece: mip_globals
// fills: Base::Dec
// mode: augment
// Globals shared by castRay() and finalizeRayCast(): the ray's maximum of the
// normalised scalar (VTK's scale/bias applied), and whether any sample was taken.
float mc_rayMax;
bool mc_rayHit;
