// mipcast piece: gradient_opacity_packed
// fills: ComputeGradientOpacity1D::Dec
// mode: replace
// VTK's gradient-opacity lookup for the packed four-component volume of the
// exact projections (mipcast/mappers/corner_packing.py): components 1-3 are
// neighbouring corners, not data, so only component 0's function applies (as
// for the one-component volume). VTK (9.2 to 9.7) declares one sampler per
// component as soon as component 0 has a gradient-opacity function (VTK's CPU
// ray caster and GetGradientOpacity() create one), but loads a table only for
// the components that have a function: the other three samplers were given
// texture unit -1, an OpenGL error (GL_INVALID_VALUE) at every frame. With one
// sampler declared, VTK's uniforms for components 1-3 do not exist. Unused
// (optimised away) when the property has no gradient-opacity function.
uniform sampler2D in_gradientTransferFunc_0[1];
float computeGradientOpacity(vec4 grad, int component)
{
  return component == 0 ? texture2D(in_gradientTransferFunc_0[0], vec2(grad.w, 0.0)).r : 1.0;
}
