// GLSL (WebGL 2) of the player: the per-camera depth pass and the view-dependent blend. Both
// follow the CPU renderer (tools/render/view_renderer.h) step by step; docs/rendering.md.
//
// Per-camera parameters live in a float texture (uCameras, 8 texels per camera, one row each)
// so that the camera count is not limited by the uniform space:
//   texel 0..2: rows of R with t.x, t.y, t.z in w      texel 3: fx, fy, cx, cy
//   texel 4: k1, k2, p1, p2                            texel 5: k3, width, height, 0
//   texel 6: atlas x, atlas y of the camera's cell     texel 7: camera centre, 0

const cameraCommon = /* glsl */ `
uniform highp sampler2D uCameras;

struct Cam {
  mat3 R;  // rows of R as given (applied as R * p below, GLSL matrices are column-major)
  vec3 t;
  vec4 intr;
  vec4 dist;
  float k3;
  vec2 size;
  ivec2 atlas;
  vec3 centre;
  vec3 axis;
};

Cam fetchCamera(int i) {
  vec4 r0 = texelFetch(uCameras, ivec2(0, i), 0);
  vec4 r1 = texelFetch(uCameras, ivec2(1, i), 0);
  vec4 r2 = texelFetch(uCameras, ivec2(2, i), 0);
  vec4 e5 = texelFetch(uCameras, ivec2(5, i), 0);
  vec4 e6 = texelFetch(uCameras, ivec2(6, i), 0);
  Cam c;
  c.R = transpose(mat3(r0.xyz, r1.xyz, r2.xyz));
  c.t = vec3(r0.w, r1.w, r2.w);
  c.intr = texelFetch(uCameras, ivec2(3, i), 0);
  c.dist = texelFetch(uCameras, ivec2(4, i), 0);
  c.k3 = e5.x;
  c.size = e5.yz;
  c.atlas = ivec2(e6.xy);
  c.centre = texelFetch(uCameras, ivec2(7, i), 0).xyz;
  c.axis = r2.xyz;
  return c;
}

// Pixel coordinates of a camera-space point with z > 0, lens distortion included.
vec2 projectCamera(Cam c, vec3 q) {
  vec2 n = q.xy / q.z;
  float r2 = dot(n, n);
  float s = 1.0 + c.dist.x * r2 + c.dist.y * r2 * r2 + c.k3 * r2 * r2 * r2;
  vec2 d = vec2(n.x * s + 2.0 * c.dist.z * n.x * n.y + c.dist.w * (r2 + 2.0 * n.x * n.x),
                n.y * s + c.dist.z * (r2 + 2.0 * n.y * n.y) + 2.0 * c.dist.w * n.x * n.y);
  return c.intr.xy * d + c.intr.zw;
}
`;

// Depth pass: the mesh seen by camera uCamera, writing 1 / z (camera depth) into a float
// target cleared to 0 (= nothing, infinitely far). Corners are projected with distortion and
// edges drawn straight, as the CPU rasteriser does. Image row v is drawn at viewport row
// H − 1 − v (GL rows count from the bottom).
export const depthVertex = /* glsl */ `
${cameraCommon}
uniform int uCamera;
uniform vec2 uNearFar;
out float vDepth;
void main() {
  Cam c = fetchCamera(uCamera);
  vec3 q = c.R * position + c.t;
  float z = max(q.z, 1e-6 * uNearFar.y);
  vec2 p = projectCamera(c, vec3(q.xy, z));
  vec2 ndc = vec2(2.0 * (p.x + 0.5) / c.size.x - 1.0, 1.0 - 2.0 * (p.y + 0.5) / c.size.y);
  float zNdc = 2.0 * (q.z - uNearFar.x) / (uNearFar.y - uNearFar.x) - 1.0;
  gl_Position = vec4(ndc * q.z, zNdc * q.z, q.z);
  vDepth = q.z;
}
`;

export const depthFragment = /* glsl */ `
precision highp float;
in float vDepth;
out vec4 outColour;
void main() { outColour = vec4(1.0 / vDepth, 0.0, 0.0, 1.0); }
`;

// The view pass: world position of the surface point per fragment.
export const blendVertex = /* glsl */ `
out vec3 vWorld;
void main() {
  vWorld = position;  // the mesh is in world coordinates (no model transform)
  gl_Position = projectionMatrix * viewMatrix * vec4(position, 1.0);
}
`;

// The view-dependent blend (MAX_CAMERAS is defined by the material).
export const blendFragment = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2DArray;
${cameraCommon}
uniform highp sampler2D uAtlas;       // RGBA8 camera images, alpha = mask
uniform highp sampler2DArray uDepth;  // per camera 1 / z, layer = camera
uniform int uCount;
uniform uint uUseMask;                // bit i set: camera i may be used (first 32 cameras)
uniform vec3 uViewCentre;
uniform vec3 uViewAxis;
uniform int uDirection;               // 0: ray, 1: axis
uniform float uSharpness;
uniform float uTolerance;
uniform int uFallback;                // 0: nearest, 1: colour
uniform vec3 uFallbackColour;
in vec3 vWorld;
out vec4 outColour;

void main() {
  vec3 P = vWorld;
  vec3 toView = uDirection == 0 ? normalize(uViewCentre - P) : uViewAxis;
  float s[MAX_CAMERAS];
  vec3 colour[MAX_CAMERAS];
  int seen = 0;
  float nearestS = 1e30;
  vec3 nearestColour = vec3(0.0);
  bool haveNearest = false;
  for (int i = 0; i < uCount; ++i) {
    if (i < 32 && (uUseMask & (1u << uint(i))) == 0u) continue;
    Cam c = fetchCamera(i);
    vec3 q = c.R * P + c.t;
    if (!(q.z > 0.0)) continue;
    vec2 p = projectCamera(c, q);
    if (!(p.x > -1.0 && p.x < c.size.x && p.y > -1.0 && p.y < c.size.y)) continue;
    ivec2 p0 = ivec2(floor(p));
    vec2 a = p - vec2(p0);
    float hidden = (1.0 + uTolerance) / q.z;  // hidden when 1 / D exceeds this
    float seenW = 0.0, maskW = 0.0;
    vec3 seenC = vec3(0.0), maskC = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
      ivec2 x = p0 + ivec2(k & 1, k >> 1);
      float b = ((k & 1) == 1 ? a.x : 1.0 - a.x) * ((k >> 1) == 1 ? a.y : 1.0 - a.y);
      if (b <= 0.0 || x.x < 0 || x.y < 0 || x.x >= int(c.size.x) || x.y >= int(c.size.y)) continue;
      vec4 texel = texelFetch(uAtlas, c.atlas + x, 0);
      if (texel.a < 0.5) continue;  // outside the camera's mask
      maskW += b;
      maskC += b * texel.rgb;
      float inverseDepth = texelFetch(uDepth, ivec3(x.x, int(c.size.y) - 1 - x.y, i), 0).r;
      if (inverseDepth > hidden) continue;
      seenW += b;
      seenC += b * texel.rgb;
    }
    if (maskW <= 0.0) continue;
    vec3 d = uDirection == 0 ? normalize(c.centre - P) : c.axis;
    vec3 e = d - toView;
    float si = 0.5 * dot(e, e);
    if (seenW > 0.0) {
      s[seen] = si;
      colour[seen] = seenC / seenW;
      ++seen;
    } else if (si < nearestS) {
      nearestS = si;
      nearestColour = maskC / maskW;
      haveNearest = true;
    }
  }
  vec3 result;
  if (seen > 0) {
    float smallest = s[0];
    for (int j = 1; j < seen; ++j) smallest = min(smallest, s[j]);
    float sum = 0.0;
    result = vec3(0.0);
    for (int j = 0; j < seen; ++j) {
      float w;
      if (smallest <= 0.0) w = s[j] <= 0.0 ? 1.0 : 0.0;
      else w = pow(smallest / s[j], 0.5 * uSharpness);
      sum += w;
      result += w * colour[j];
    }
    result /= sum;
  } else if (uFallback == 0 && haveNearest) {
    result = nearestColour;
  } else {
    result = uFallbackColour;
  }
  outColour = vec4(result, 1.0);
}
`;
