// mipcast piece: demip_helpers
// fills: Shading::Dec
// mode: augment
// Depth-enhanced MIP (docs/methods.md#demip, mipcast/mappers/demip.py): the
// globals the DEMIP family's hook pieces (demip_hooks, demip_lmip_hooks,
// demip_attenuated_hooks, demip_mida_hooks, demip_two_pass_*_hooks, run by
// sampled_loop) hand to the colour exit (demip_color) and the float readout
// (demip_readout); the first march's level bookkeeping, the second march's
// hooks (the same-material search), and the depth and sphere helpers.
//
// Coordinates: "texture" is the space of g_dataPos (VTK's adjusted texture
// coordinates, point bounds [in_texMin, in_texMax]); "eye" is VTK's camera
// space (the camera looks down -z), so a point's view distance is -z.
int mc_matchIndex;   // loop index of the first same-material sample; -1: no DEMIP term
float mc_depth;      // its normalised depth in [0, 1] (valid when mc_matchIndex >= 0)
vec3 mc_hitTex;      // its position (texture coordinates)
vec4 mc_composite;   // MIDA's premultiplied colour and opacity (demip_mida_hooks)

// The material window in raw texel units: (floor, ceiling, band, low) with
// band = eps * (ceiling - floor) and low = floor + u_mc_floorTolerance *
// (ceiling - floor), the value samples must exceed to count as tissue.
vec4 mcMaterialWindow()
{
  float floorRaw = mcRaw(u_mc_floor);
  float ceilingRaw = mcRaw(u_mc_ceiling);
  float width = ceilingRaw - floorRaw;
  return vec4(floorRaw, ceilingRaw, u_mc_materialThreshold * width, floorRaw + u_mc_floorTolerance * width);
}

mat4 mcTextureToWorld()
{
  return in_volumeMatrix[0] * inverse(ip_inverseTextureDataAdjusted);
}

// View distances (-z in eye space) of the box corners nearest to and
// farthest from the camera along the view direction.
vec2 mcBoxViewRange(mat4 texToEye)
{
  vec3 g = -vec3(texToEye[0][2], texToEye[1][2], texToEye[2][2]);
  vec3 a = g * in_texMin[0];
  vec3 b = g * in_texMax[0];
  vec3 low = min(a, b);
  vec3 high = max(a, b);
  float c = -texToEye[3][2];
  return vec2(c + low.x + low.y + low.z, c + high.x + high.y + high.z);
}

// OpenGL window depth (0 at the near clipping plane, 1 at the far one) of a
// point at view distance d; d is clamped to the clipping range first.
float mcWindowDepth(float d)
{
  mat4 p = in_projectionMatrix;
  float nearPlane = (p[3][2] + p[3][3]) / (p[2][2] + p[2][3]);
  float farPlane = (p[3][2] - p[3][3]) / (p[2][2] - p[2][3]);
  vec4 clip = p * vec4(0.0, 0.0, -clamp(d, nearPlane, farPlane), 1.0);
  return 0.5 * clip.z / clip.w + 0.5;
}

// Normalised depth of the sample at hitTex on the ray entering the box at
// entryTex, by u_mc_depthMode (0 window, 1 steps, 2 entry_plus_length,
// 3 eye_distance); 0 = the box's near side, 1 = its far side, clamped. With
// a slab (at any angle to the view) near and far are those of the part of
// the box inside the slab (u_mc_slabDepth, u_mc_slabDistance: computed per
// render in mipcast/mappers/clip_uniforms.py, else +-1e30), and steps and
// entry_plus_length measure from where the ray enters the slab (its faces
// u_mc_slabNear/u_mc_slabFar as texture-space rows, else (0, 0, 0, 1),
// which keep every point: the entry stays the box entry).
float mcDemipDepth(vec3 hitTex, vec3 entryTex)
{
  float slabLo = 0.0;
  float slabHi = 1.0e30;
  mcClipPlane(u_mc_slabNear, entryTex, g_dirStep, slabLo, slabHi);
  mcClipPlane(u_mc_slabFar, entryTex, g_dirStep, slabLo, slabHi);
  entryTex += max(slabLo, 0.0) * g_dirStep;
  mat4 texToEye = in_modelViewMatrix * mcTextureToWorld();
  vec3 hitEye = (texToEye * vec4(hitTex, 1.0)).xyz;
  vec3 entryEye = (texToEye * vec4(entryTex, 1.0)).xyz;
  vec2 range = mcBoxViewRange(texToEye);
  range = vec2(max(range.x, u_mc_slabDepth.x), min(range.y, u_mc_slabDepth.y));
  float extent = max(range.y - range.x, 1.0e-30);
  float depth;
  if (u_mc_depthMode == 0)
  {
    float nearDepth = mcWindowDepth(range.x);
    float farDepth = mcWindowDepth(range.y);
    depth = (mcWindowDepth(-hitEye.z) - nearDepth) / max(farDepth - nearDepth, 1.0e-30);
  }
  else if (u_mc_depthMode == 1)
  {
    depth = length(hitEye - entryEye) / extent;
  }
  else if (u_mc_depthMode == 2)
  {
    depth = (-entryEye.z - range.x + length(hitEye - entryEye)) / extent;
  }
  else if (in_projectionMatrix[3][3] > 0.5)  // eye_distance, parallel projection
  {
    depth = (-hitEye.z - range.x) / extent;
  }
  else  // eye_distance, perspective: distance from the eye point
  {
    vec3 eyeTex = (ip_inverseTextureDataAdjusted * in_inverseVolumeMatrix[0]
                   * in_inverseModelViewMatrix * vec4(0.0, 0.0, 0.0, 1.0)).xyz;
    vec3 nearest = clamp(eyeTex, in_texMin[0], in_texMax[0]);
    vec3 farthest = mix(in_texMin[0], in_texMax[0],
                        vec3(lessThan(eyeTex, 0.5 * (in_texMin[0] + in_texMax[0]))));
    float nearDistance = length((texToEye * vec4(nearest, 1.0)).xyz);
    float farDistance = length((texToEye * vec4(farthest, 1.0)).xyz);
    nearDistance = max(nearDistance, u_mc_slabDistance.x);
    farDistance = min(farDistance, u_mc_slabDistance.y);
    depth = (length(hitEye) - nearDistance) / max(farDistance - nearDistance, 1.0e-30);
  }
  return clamp(depth, 0.0, 1.0);
}

// Colour sphere (Eq. 2): the direction from the box centre to the hit, in
// world coordinates, against the sphere's front pole u_mc_sphereAxis;
// back colour at the opposite pole, linear in the pole-axis coordinate.
vec3 mcSphereColor(vec3 hitTex)
{
  vec3 fromCentre = (mcTextureToWorld() * vec4(hitTex - 0.5 * (in_texMin[0] + in_texMax[0]), 0.0)).xyz;
  float size = length(fromCentre);
  float along = size > 0.0 ? dot(fromCentre, u_mc_sphereAxis) / size : 0.0;
  return mix(u_mc_sphereBack, u_mc_sphereFront, 0.5 + 0.5 * along);
}

// Pseudo-chromadepth (Ropinski et al.): hue from red (depth 0, near) through
// yellow, green and cyan to blue (depth 1, far); full saturation and value.
vec3 mcChromaColor(float depth)
{
  float hue = 2.0 / 3.0 * depth;
  return clamp(abs(fract(hue + vec3(1.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
}

// The material of a raw value v is its place in the transfer functions'
// window, clamp((v - floor) / (ceiling - floor), 0, 1) (u_mc_floor and
// u_mc_ceiling, normalised): mcBeginMaterial once per ray, then mcMaterial.
float mc_floorRaw;
float mc_toMaterial;

void mcBeginMaterial()
{
  mc_floorRaw = mcRaw(u_mc_floor);
  mc_toMaterial = 1.0 / (mcRaw(u_mc_ceiling) - mc_floorRaw);
}

float mcMaterial(float value)
{
  return clamp((value - mc_floorRaw) * mc_toMaterial, 0.0, 1.0);
}

// MIDA's step (Bruckner & Groller, gamma 0) at one sample of material
// `material`, opacity `alpha` and colour `color`: what is in front fades by
// beta = 1 - (how much the material exceeds the running maximum), then the
// sample is composited front to back into `sum` (premultiplied). Returns
// beta. The one definition of the single-texture and the brick hooks.
float mcMidaStep(float material, float alpha, vec3 color, inout float runMaterial, inout vec4 sum)
{
  float beta = 1.0 - max(material - runMaterial, 0.0);
  runMaterial = max(runMaterial, material);
  float fresh = (1.0 - beta * sum.a) * alpha;
  sum = vec4(beta * sum.rgb + fresh * color, beta * sum.a + fresh);
  return beta;
}

// DEMIP's two marches over the samples of sampled_loop.
//
// The material is monotone, so "within eps of the maximum's material, and
// above the floor" is the raw test
//   v >= min(max, ceiling) - band  &&  v > low
// (mcMaterialWindow; a background exactly at the floor stays background).
//
// March 1 (mcDemipBeginRay, then mcDemipSample at every sample) takes the
// maximum and follows the level of the running maximum,
// floor((min(v, ceiling) - low) / band) (monotone in v), remembering where
// it first reached the level below its current one. Every earlier sample
// lies more than one band below the final maximum and cannot match (nor can
// samples at or below low), so march 2 starts there: the result equals a
// march from the ray start. Levels are at least 1e-6 of the window wide, so
// that they stay distinct in float32 for tiny eps.
vec4 mc_window;      // mcMaterialWindow()
float mc_perLevel;
float mc_levelBias;
float mc_level;      // level of the running maximum
int mc_entered;      // where the running maximum entered mc_level
int mc_start;        // where it first reached mc_level - 1 or above: march 2 starts here
float mc_sameAbove;  // march 2's threshold, min(max, ceiling) - band

void mcDemipBeginRay()
{
  mc_window = mcMaterialWindow();
  mc_perLevel = 1.0 / max(mc_window.z, 1.0e-6 * (mc_window.y - mc_window.x));
  mc_levelBias = -mc_window.w * mc_perLevel;
  mc_level = -1.0e30;
  mc_entered = 0;
  mc_start = 0;
  mc_rayMax = -3.0e38;  // below every raw texel value (mip_hooks)
  mc_matchIndex = -1;
}

void mcDemipSample(float value, int i)
{
  mc_rayMax = max(mc_rayMax, value);
  float sampleLevel = floor(min(value, mc_window.y) * mc_perLevel + mc_levelBias);
  bool up = sampleLevel > mc_level;
  mc_start = up ? (sampleLevel == mc_level + 1.0 ? mc_entered : i) : mc_start;
  mc_entered = up ? i : mc_entered;
  mc_level = max(mc_level, sampleLevel);
}

// March 2, sampled_loop's second-march hooks (on with MC_SECOND_MARCH): from
// sample mc_start on, the first sample of the same material as the raw
// maximum mc_rayMax; sets mc_matchIndex, mc_hitTex and mc_depth. The
// maximum's own sample always matches, so the march ends at it at the
// latest. Skipped when nothing uses the depth (u_mc_needDepth = 0) or the
// maximum is not above the floor.
bool mcBeginSecondMarch(inout int first, inout int count)
{
  first = mc_start;
  mc_sameAbove = min(mc_rayMax, mc_window.y) - mc_window.z;
  return mc_rayMax > mc_window.w && u_mc_needDepth > 0.5;
}

bool mcSecondSample(float value, int i)
{
  return value >= mc_sameAbove && value > mc_window.w;
}

void mcEndSecondMarch(int found)
{
  mc_matchIndex = found;
  if (mc_matchIndex >= 0)
  {
    mc_hitTex = g_dataPos + float(mc_matchIndex) * g_dirStep;
    mc_depth = mcDemipDepth(mc_hitTex, g_dataPos - g_rayJitter);
  }
}
