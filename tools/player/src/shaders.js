// GLSL (WebGL 2) of the player: the per-camera depth pass, the YUV → RGB conversion of the
// decoded textures and the view-dependent blend. All follow the C++ side step by step
// (tools/render/view_renderer.h, common/media/yuv.cpp); docs/rendering.md.
//
// Per-camera parameters live in a float texture (uCameras, 8 texels per camera, one row each)
// so that the camera count is not limited by the uniform space:
//   texel 0..2: rows of R with t.x, t.y, t.z in w      texel 3: fx, fy, cx, cy
//   texel 4: k1, k2, p1, p2                            texel 5: k3, width, height, used
//   (used: 1, or 0 for a camera left out with exclude=)
//   texel 6: texture box x, y, width, height          texel 7: camera centre, 0

const cameraCommon = /* glsl */ `
uniform highp sampler2D uCameras;

struct Cam {
  mat3 R;  // rows of R as given (applied as R * p below, GLSL matrices are column-major)
  vec3 t;
  vec4 intr;
  vec4 dist;
  float k3;
  vec2 size;
  ivec4 box;
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
  c.box = ivec4(e6);
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

// A decoded texture's RGB at a pixel of its box, exactly as 3dvo-dec converts it for its PNGs
// (common/media/yuv.cpp: libswscale, BT.601 limited range, SWS_BILINEAR | SWS_ACCURATE_RND |
// SWS_BITEXACT | SWS_FULL_CHR_H_INT, FFmpeg 5.1). Integer arithmetic reproduces libswscale's
// result bit for bit (checked on random pictures against the library, docs/rendering.md):
// - chroma upsampled horizontally with centre-sited bilinear taps (3/4, 1/4; the edge taps
//   clamped), exact in libswscale's 15-bit intermediate;
// - vertically, libswscale's two-tap RGB output takes, where the second tap's weight is below
//   1/2, the first chroma row alone, else the mean of both rows (so the last luma row averages
//   the last two chroma rows);
// - R, G, B = ((Y − 16)·76312 + 32768 + chroma terms) >> 16 with the coefficients 13075
//   (V→R), −6660 (V→G), −3209 (U→G), 16525 (U→B) in units of 1/8 chroma step, clipped to 0..255,
//   where a sum past 2^25 (a 32-bit overflow inside libswscale: very bright blue) gives 0.
export const yuvToRgb = /* glsl */ `
uniform highp sampler2DArray uY;      // per camera its box's luma, layer = camera
uniform highp sampler2DArray uU;
uniform highp sampler2DArray uV;

int sampleAt(highp sampler2DArray plane, ivec2 p, int layer) {
  return int(texelFetch(plane, ivec3(p, layer), 0).r * 255.0 + 0.5);
}

// The two taps of 2x upsampling output sample i from n samples: (first sample, second's weight
// in quarters).
ivec2 upsamplingTaps(int i, int n) {
  ivec2 t = (i & 1) == 0 ? ivec2(i / 2 - 1, 3) : ivec2((i - 1) / 2, 1);
  if (t.x < 0) return ivec2(0, 0);
  if (t.x + 1 > n - 1) return ivec2(n - 2, 4);
  return t;
}

// Chroma at luma pixel p of a box of luma size 'size', in 1/8 steps minus 1024.
int chromaAt(highp sampler2DArray plane, ivec2 p, ivec2 size, int layer) {
  ivec2 h = upsamplingTaps(p.x, size.x / 2), v = upsamplingTaps(p.y, size.y / 2);
  int row0 = sampleAt(plane, ivec2(h.x, v.x), layer) * (4 - h.y) +
             sampleAt(plane, ivec2(h.x + 1, v.x), layer) * h.y;
  if (v.y < 2) return 2 * row0 - 1024;
  int row1 = sampleAt(plane, ivec2(h.x, v.x + 1), layer) * (4 - h.y) +
             sampleAt(plane, ivec2(h.x + 1, v.x + 1), layer) * h.y;
  return row0 + row1 - 1024;
}

float channel(int sum) {
  if (sum < 0 || sum >= (1 << 25)) return 0.0;
  if (sum >= (1 << 24)) return 1.0;
  return float(sum >> 16) / 255.0;
}

// RGB (0..1) at pixel p of camera 'layer''s box of size 'size'.
vec3 boxRgb(ivec2 p, ivec2 size, int layer) {
  int y = (sampleAt(uY, p, layer) - 16) * 76312 + 32768;
  int u = chromaAt(uU, p, size, layer), v = chromaAt(uV, p, size, layer);
  return vec3(channel(y + v * 13075), channel(y - v * 6660 - u * 3209), channel(y + u * 16525));
}
`;

// The conversion pass: a camera's box as RGB into its layer of an RGBA8 array target, once per
// decoded frame (the blend then reads one texel per sample). Fragment (x, y) of the viewport is
// box pixel (x, y), row 0 at the top, which texelFetch reads back at (x, y).
export const convertVertex = /* glsl */ `
void main() { gl_Position = vec4(position.xy, 0.0, 1.0); }
`;

export const convertFragment = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2DArray;
${yuvToRgb}
uniform int uLayer;
uniform vec2 uSize;  // the box, in pixels
out vec4 outColour;
void main() { outColour = vec4(boxRgb(ivec2(gl_FragCoord.xy), ivec2(uSize), uLayer), 1.0); }
`;

// Blending=ulr's edge distance maps (tools/render/view_renderer.h edgeDistances), per camera
// from its depth layer (1 / z, 0 = outside the shape) in two passes of one fragment per texel
// (the viewport at the camera's size; layout as the depth layer's). A texel is an edge texel
// when it is inside the shape and a 4-neighbour inside the image is outside it or its depth
// differs by more than EDGE_DEPTH_JUMP (kEdgeDepthJump) times the nearer one's; for inverse
// depths a and b that is |a − b| > EDGE_DEPTH_JUMP · min(a, b). The exact Euclidean distance to
// the nearest edge texel, capped at uEdgeWidth, is found separably: pass 1 writes per texel the
// distance along its row (|dx| ≤ uRadius = ceil(uEdgeWidth), else 1e4), pass 2 the least
// sqrt(row² + dy²) over |dy| ≤ uRadius.
const edgeCommon = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2DArray;
uniform int uLayer;
uniform vec2 uSize;    // the camera's image size
uniform int uRadius;
uniform float uEdgeWidth;
out vec4 outColour;
`;

export const edgeRowFragment = /* glsl */ `
${edgeCommon}
uniform highp sampler2DArray uDepth;
const float EDGE_DEPTH_JUMP = 0.05;
float inverseDepthAt(ivec2 p) { return texelFetch(uDepth, ivec3(p, uLayer), 0).r; }
bool isEdge(ivec2 p) {
  ivec2 size = ivec2(uSize);
  if (p.x < 0 || p.y < 0 || p.x >= size.x || p.y >= size.y) return false;
  float a = inverseDepthAt(p);
  if (!(a > 0.0)) return false;
  for (int k = 0; k < 4; ++k) {
    ivec2 n = p + (k < 2 ? ivec2(2 * k - 1, 0) : ivec2(0, 2 * k - 5));
    if (n.x < 0 || n.y < 0 || n.x >= size.x || n.y >= size.y) continue;
    float b = inverseDepthAt(n);
    if (!(b > 0.0) || abs(a - b) > EDGE_DEPTH_JUMP * min(a, b)) return true;
  }
  return false;
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float row = 1e4;
  for (int dx = -uRadius; dx <= uRadius; ++dx)
    if (isEdge(p + ivec2(dx, 0))) row = min(row, float(abs(dx)));
  outColour = vec4(row, 0.0, 0.0, 1.0);
}
`;

export const edgeFragment = /* glsl */ `
${edgeCommon}
uniform highp sampler2DArray uRows;  // pass 1
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float d = uEdgeWidth;
  for (int dy = -uRadius; dy <= uRadius; ++dy) {
    int y = p.y + dy;
    if (y < 0 || y >= int(uSize.y)) continue;
    float row = texelFetch(uRows, ivec3(p.x, y, uLayer), 0).r;
    d = min(d, sqrt(row * row + float(dy * dy)));
  }
  outColour = vec4(d, 0.0, 0.0, 1.0);
}
`;

// The view-dependent blend (MAX_CAMERAS is defined by the material). A camera's texel takes
// part when it lies in the camera's image and texture box and inside the object's shape there:
// the pixels the decoded mesh covers in that camera, i.e. where its depth map is not empty
// (docs/bitstream.md section 6: the shape is not transmitted).
export const blendFragment = /* glsl */ `
precision highp float;
precision highp int;
precision highp sampler2DArray;
${cameraCommon}
uniform highp sampler2DArray uRgb;    // per camera its box's RGB (the conversion pass)
uniform highp sampler2DArray uDepth;  // per camera 1 / z, layer = camera
uniform highp sampler2DArray uEdge;   // per camera the edge distance (edgeFragment), ulr only
uniform int uCount;
uniform vec3 uViewCentre;
uniform vec3 uViewAxis;
uniform int uDirection;               // 0: ray, 1: axis
uniform float uSharpness;
uniform int uBlending;                // 0: angle, 1: ulr
uniform float uResolutionPenalty;
uniform float uEdgeWidth;
uniform float uViewFocal;             // the view's fx (pixels)
uniform float uTolerance;
uniform int uFallback;                // 0: nearest, 1: colour, 2: fill
uniform vec3 uFallbackColour;
in vec3 vWorld;
out vec4 outColour;
const float EDGE_FLOOR = 1e-3;  // kEdgeFloor

void main() {
  vec3 P = vWorld;
  vec3 toView = uDirection == 0 ? normalize(uViewCentre - P) : uViewAxis;
  float s[MAX_CAMERAS];
  float edge[MAX_CAMERAS];  // ulr: the edge factor e_i
  vec3 colour[MAX_CAMERAS];
  float viewFootprint = dot(P - uViewCentre, uViewAxis) / uViewFocal;
  int seen = 0;
  float nearestS = 1e30;
  vec3 nearestColour = vec3(0.0);
  bool haveNearest = false;
  for (int i = 0; i < uCount; ++i) {
    if (texelFetch(uCameras, ivec2(5, i), 0).w == 0.0) continue;  // left out (exclude=)
    Cam c = fetchCamera(i);
    vec3 q = c.R * P + c.t;
    if (!(q.z > 0.0)) continue;
    vec2 p = projectCamera(c, q);
    if (!(p.x > -1.0 && p.x < c.size.x && p.y > -1.0 && p.y < c.size.y)) continue;
    ivec2 p0 = ivec2(floor(p));
    vec2 a = p - vec2(p0);
    float hidden = (1.0 + uTolerance) / q.z;  // hidden when 1 / D exceeds this
    float seenW = 0.0, maskW = 0.0, edgeD = 0.0;
    vec3 seenC = vec3(0.0), maskC = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
      ivec2 x = p0 + ivec2(k & 1, k >> 1);
      float b = ((k & 1) == 1 ? a.x : 1.0 - a.x) * ((k >> 1) == 1 ? a.y : 1.0 - a.y);
      if (b <= 0.0 || x.x < 0 || x.y < 0 || x.x >= int(c.size.x) || x.y >= int(c.size.y)) continue;
      ivec2 inBox = x - c.box.xy;
      if (inBox.x < 0 || inBox.y < 0 || inBox.x >= c.box.z || inBox.y >= c.box.w) continue;
      ivec3 at = ivec3(x.x, int(c.size.y) - 1 - x.y, i);
      float inverseDepth = texelFetch(uDepth, at, 0).r;
      if (!(inverseDepth > 0.0)) continue;  // outside the object's shape in this camera
      vec3 texel = texelFetch(uRgb, ivec3(inBox, i), 0).rgb;
      maskW += b;
      maskC += b * texel;
      if (inverseDepth > hidden) continue;
      seenW += b;
      seenC += b * texel;
      if (uBlending == 1 && uEdgeWidth > 0.0) edgeD += b * texelFetch(uEdge, at, 0).r;
    }
    if (maskW <= 0.0) continue;
    vec3 d = uDirection == 0 ? normalize(c.centre - P) : c.axis;
    vec3 e = d - toView;
    float si = 0.5 * dot(e, e);
    if (seenW > 0.0) {
      if (uBlending == 1) {  // resolution penalty (view_weights.h ulrWeights)
        float r = q.z / c.intr.x / viewFootprint;
        si *= 1.0 + uResolutionPenalty * max(0.0, r - 1.0);
        edge[seen] = uEdgeWidth > 0.0 ? clamp(edgeD / seenW / uEdgeWidth, EDGE_FLOOR, 1.0) : 1.0;
      } else {
        edge[seen] = 1.0;
      }
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
      w *= edge[j];
      sum += w;
      result += w * colour[j];
    }
    result /= sum;
  } else if (uFallback == 0 && haveNearest) {
    result = nearestColour;
  } else if (uFallback == 2) {
    outColour = vec4(0.0, 0.0, 0.0, 0.5);  // filled by the push-pull passes (fillFragment)
    return;
  } else {
    result = uFallbackColour;
  }
  outColour = vec4(result, 1.0);
}
`;

// Fallback=fill (tools/render/view_renderer.cpp fillFromBlended): push-pull over the blended
// frame. The frame target holds the blend pass's output: alpha 1 where blended, 0.5 where no
// camera sees the point (to be filled), 0 where the mesh does not cover the pixel. Levels 1, 2,
// … hold image rows top first (texel row y = image row y); the frame target and the canvas hold
// GL rows (bottom first), so their row is flipped. A level's weight is its alpha (0 or 1).
const fillCommon = /* glsl */ `
precision highp float;
precision highp int;
uniform highp sampler2D uFine;    // push: the finer level; pull: the level itself
uniform highp sampler2D uCoarse;  // pull: the coarser level, already pulled
uniform ivec2 uFineSize;
uniform ivec2 uCoarseSize;
uniform bool uFineIsFrame;        // uFine is the frame target (GL rows, alpha 0.5 = to fill)
uniform vec3 uFlat;               // no blended pixel at all: the flat colour
out vec4 outColour;

// Colour and weight (0 or 1) of image pixel p of the fine level.
vec4 fineAt(ivec2 p) {
  if (!uFineIsFrame) return texelFetch(uFine, p, 0);
  vec4 t = texelFetch(uFine, ivec2(p.x, uFineSize.y - 1 - p.y), 0);
  return t.a > 0.75 ? vec4(t.rgb, 1.0) : vec4(0.0);
}

// The pulled coarse level, bilinear at fine image pixel p (coarse centres at 2X + 0.5, clamped).
vec3 coarseAt(ivec2 p) {
  vec2 c = clamp((vec2(p) - 0.5) / 2.0, vec2(0.0), vec2(uCoarseSize - 1));
  ivec2 c0 = ivec2(c);
  ivec2 c1 = min(c0 + 1, uCoarseSize - 1);
  vec2 a = c - vec2(c0);
  return mix(mix(texelFetch(uCoarse, c0, 0).rgb, texelFetch(uCoarse, ivec2(c1.x, c0.y), 0).rgb, a.x),
             mix(texelFetch(uCoarse, ivec2(c0.x, c1.y), 0).rgb, texelFetch(uCoarse, c1, 0).rgb, a.x),
             a.y);
}
`;

// One level coarser: per 2 × 2 block the mean of its pixels of weight 1 (weight 1 if any).
export const pushFragment = /* glsl */ `
${fillCommon}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 sum = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    ivec2 f = 2 * p + ivec2(k & 1, k >> 1);
    if (f.x < uFineSize.x && f.y < uFineSize.y) sum += fineAt(f);
  }
  outColour = sum.a > 0.0 ? vec4(sum.rgb / sum.a, 1.0) : vec4(0.0);
}
`;

// A level filled from the coarser one (the top level: from the flat colour).
export const pullFragment = /* glsl */ `
${fillCommon}
uniform bool uTop;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 own = fineAt(p);
  if (own.a > 0.0) outColour = own;
  else outColour = vec4(uTop ? uFlat : coarseAt(p), 1.0);
}
`;

// Level 0 onto the canvas (GL rows): the frame as drawn, the pixels to fill from level 1.
export const fillFragment = /* glsl */ `
${fillCommon}
void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  vec4 t = texelFetch(uFine, g, 0);
  if (t.a > 0.25 && t.a < 0.75) t = vec4(coarseAt(ivec2(g.x, uFineSize.y - 1 - g.y)), 1.0);
  outColour = t;
}
`;
