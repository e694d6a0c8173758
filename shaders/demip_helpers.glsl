// mipcast piece: demip_helpers
// fills: Shading::Dec
// mode: augment
// Depth-enhanced MIP (docs/methods.md#demip, mipcast/mappers/demip.py): the
// globals the ray loop (demip_loop) hands to the colour exit (demip_color)
// and the float readout (demip_readout), and the depth and sphere helpers.
//
// Coordinates: "texture" is the space of g_dataPos (VTK's adjusted texture
// coordinates, point bounds [in_texMin, in_texMax]); "eye" is VTK's camera
// space (the camera looks down -z), so a point's view distance is -z.
int mc_matchIndex;   // loop index of the first same-material sample; -1: no DEMIP term
float mc_depth;      // its normalised depth in [0, 1] (valid when mc_matchIndex >= 0)
vec3 mc_hitTex;      // its position (texture coordinates)
vec4 mc_composite;   // MIDA's premultiplied colour and opacity (demip_mida_loop)

// Normalised scalar (VTK's scale/bias) -> raw texel value.
float mcDemipRaw(float normalised)
{
  return (normalised - in_volume_bias[0].r) / in_volume_scale[0].r;
}

// Number of samples on this ray, exactly as mip_sampled_loop counts them:
// the first at g_dataPos (one step after the box entry), then every
// g_dirStep while inside the point bounds and before the depth-buffer /
// clipping termination. Sample k sits at g_dataPos + k * g_dirStep.
int mcSampleCount()
{
  vec3 limit = mix(in_texMin[0], in_texMax[0], vec3(greaterThan(g_dirStep, vec3(0.0))));
  vec3 toExit = (limit - g_dataPos) / g_dirStep;
  toExit = mix(toExit, vec3(1.0e30), vec3(equal(g_dirStep, vec3(0.0))));
  int count = 1 + int(max(0.0, floor(min(min(toExit.x, toExit.y), toExit.z))));
  return min(count, int(ceil(max(g_terminatePointMax, 0.0))) + 1);
}

// The material window in raw texel units: (floor, ceiling, band, low) with
// band = eps * (ceiling - floor) and low = floor + u_mc_floorTolerance *
// (ceiling - floor), the value samples must exceed to count as tissue.
vec4 mcMaterialWindow()
{
  float floorRaw = mcDemipRaw(u_mc_floor);
  float ceilingRaw = mcDemipRaw(u_mc_ceiling);
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
// 3 eye_distance); 0 = the box's near side, 1 = its far side, clamped.
float mcDemipDepth(vec3 hitTex, vec3 entryTex)
{
  mat4 texToEye = in_modelViewMatrix * mcTextureToWorld();
  vec3 hitEye = (texToEye * vec4(hitTex, 1.0)).xyz;
  vec3 entryEye = (texToEye * vec4(entryTex, 1.0)).xyz;
  vec2 range = mcBoxViewRange(texToEye);
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

// The first march's bookkeeping (shared by the DEMIP and LMIP loops): the
// level of the running maximum, where it entered that level, and where it
// first reached the level below (the second march may start there).
void mcTrackLevel(float sampleLevel, int i, inout float level, inout int entered, inout int start)
{
  bool up = sampleLevel > level;
  start = up ? (sampleLevel == level + 1.0 ? entered : i) : start;
  entered = up ? i : entered;
  level = max(level, sampleLevel);
}

// March 2: from sample `start` on, the first sample of the same material as
// the raw maximum `rayMax` (v >= min(rayMax, ceiling) - band && v > low);
// sets mc_matchIndex, mc_hitTex and mc_depth. The maximum's own sample
// always matches, so the loop ends at it at the latest.
void mcFindSameMaterial(int start, int count, float rayMax, vec4 window)
{
  float threshold = min(rayMax, window.y) - window.z;
  for (int j = start; j < count; ++j)
  {
    float value = texture3D(in_volume[0], g_dataPos + float(j) * g_dirStep).r;
    if (value >= threshold && value > window.w)
    {
      mc_matchIndex = j;
      break;
    }
  }
  if (mc_matchIndex >= 0)
  {
    mc_hitTex = g_dataPos + float(mc_matchIndex) * g_dirStep;
    mc_depth = mcDemipDepth(mc_hitTex, g_dataPos - g_rayJitter);
  }
}
