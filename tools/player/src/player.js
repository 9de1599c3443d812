// The 3DVO web player: plays the folder `3dvo-render --Mode=export` writes (scene.json, a
// binary mesh and an RGBA texture atlas per frame) with the view-dependent texture weights of
// the CPU renderer, computed per fragment in a shader (src/shaders.js). docs/rendering.md.
//
// URL parameters (all optional):
//   data=URL          the exported folder (default: data/)
//   camera=NAME       start at this dataset camera's pose and intrinsics, the canvas at its size
//   frame=N           start at frame N (default 0)
//   play=1            start playing
//   direction=ray|axis, sharpness=K, tolerance=T, fallback=nearest|colour
//                     override the weighting options stored in scene.json
//   exclude=NAME,...  cameras whose textures are not used (leave-one-out views)
//
// window.tdvoPlayer is the page's test interface: state ('loading' | 'ready' | 'error'),
// error, frame, playing, setFrame(n), play(), pause(), viewFromCamera(name), orbit(degrees),
// capture() → {width, height, rgba: base64}.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { cameraCentre, setIntrinsics, setPose } from './camera_math.js';
import { blendFragment, blendVertex, depthFragment, depthVertex } from './shaders.js';

const params = new URLSearchParams(window.location.search);
const api = { state: 'loading', error: '', frame: 0, playing: false };
window.tdvoPlayer = api;

const statusLine = document.getElementById('status');
function fail(message) {
  api.state = 'error';
  api.error = String(message);
  statusLine.textContent = 'error: ' + message;
  console.error(message);
}

function framePath(pattern, n) {
  return pattern.replace(/%0?(\d*)d/, (_, width) => String(n).padStart(Number(width || 0), '0'));
}

async function fetchOk(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  return response;
}

// One frame's mesh (binary layout in tools/render/player_export.h) and texture atlas.
async function loadFrame(base, scene, n) {
  const [meshBuffer, atlasBlob] = await Promise.all([
    fetchOk(base + framePath(scene.meshes, n)).then((r) => r.arrayBuffer()),
    fetchOk(base + framePath(scene.textures, n)).then((r) => r.blob()),
  ]);
  const header = new DataView(meshBuffer, 0, 8);
  const vertices = header.getUint32(0, true), triangles = header.getUint32(4, true);
  if (meshBuffer.byteLength !== 8 + 12 * (vertices + triangles))
    throw new Error(`mesh of frame ${n}: size does not match its header`);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position',
                        new THREE.BufferAttribute(new Float32Array(meshBuffer, 8, 3 * vertices), 3));
  geometry.setIndex(new THREE.BufferAttribute(
      new Uint32Array(meshBuffer, 8 + 12 * vertices, 3 * triangles), 1));
  geometry.computeBoundingSphere();
  // Decoded as stored: no colour-space conversion, no premultiplication (alpha is the mask).
  const bitmap = await createImageBitmap(
      atlasBlob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none', imageOrientation: 'none' });
  if (bitmap.width !== scene.atlas.width || bitmap.height !== scene.atlas.height)
    throw new Error(`texture atlas of frame ${n}: ${bitmap.width}x${bitmap.height}, ` +
                    `scene.json says ${scene.atlas.width}x${scene.atlas.height}`);
  const atlas = new THREE.Texture(bitmap);
  atlas.flipY = false;
  atlas.premultiplyAlpha = false;
  atlas.colorSpace = THREE.NoColorSpace;
  atlas.generateMipmaps = false;
  atlas.minFilter = atlas.magFilter = THREE.NearestFilter;
  atlas.needsUpdate = true;
  return { geometry, atlas };
}

// Per-camera parameters as a float texture (layout in src/shaders.js).
function cameraTexture(cameras) {
  const data = new Float32Array(cameras.length * 8 * 4);
  cameras.forEach((c, i) => {
    const o = i * 32;
    for (let r = 0; r < 3; ++r) data.set([...c.R[r], c.t[r]], o + 4 * r);
    data.set([c.fx, c.fy, c.cx, c.cy], o + 12);
    data.set(c.distortion.slice(0, 4), o + 16);
    data.set([c.distortion[4], c.width, c.height, 0], o + 20);
    data.set([c.atlasX, c.atlasY, 0, 0], o + 24);
    data.set([...cameraCentre(c.R, c.t), 0], o + 28);
  });
  const texture = new THREE.DataTexture(data, 8, cameras.length, THREE.RGBAFormat, THREE.FloatType);
  texture.minFilter = texture.magFilter = THREE.NearestFilter;
  texture.needsUpdate = true;
  return texture;
}

async function main() {
  const base = (params.get('data') || 'data/').replace(/\/?$/, '/');
  const scene = await fetchOk(base + 'scene.json').then((r) => r.json());
  if (scene.format !== '3dvo-player' || scene.version !== 1)
    throw new Error(base + 'scene.json: not a 3dvo-player scene of version 1');
  const cameras = scene.cameras;
  const weights = { ...scene.weights };
  if (params.has('direction')) weights.direction = params.get('direction');
  if (params.has('sharpness')) weights.sharpness = Number(params.get('sharpness'));
  if (params.has('tolerance')) weights.depthTolerance = Number(params.get('tolerance'));
  if (params.has('fallback')) weights.fallback = params.get('fallback');
  const excluded = new Set((params.get('exclude') || '').split(',').filter((s) => s));
  let useMask = 0;
  cameras.forEach((c, i) => { if (i < 32 && !excluded.has(c.name)) useMask |= 1 << i; });

  // Canvas: a dataset camera's size when starting from its pose, else the window.
  const start = params.get('camera');
  const startCamera = start ? cameras.find((c) => c.name === start) : null;
  if (start && !startCamera) throw new Error(`no camera named '${start}' in scene.json`);
  const canvas = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer(
      { canvas, antialias: false, alpha: true, preserveDrawingBuffer: true });
  if (!renderer.capabilities.isWebGL2) throw new Error('WebGL 2 is needed');
  renderer.setPixelRatio(1);
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;  // colours written as computed
  renderer.setClearColor(new THREE.Color(...scene.weights.background.map((v) => v / 255)), 0);
  const maxSide = renderer.capabilities.maxTextureSize;
  if (scene.atlas.width > maxSide || scene.atlas.height > maxSide)
    throw new Error(`the texture atlas (${scene.atlas.width}x${scene.atlas.height}) exceeds ` +
                    `this GPU's ${maxSide}; export fewer cameras`);

  let width, height;
  const view = new THREE.PerspectiveCamera();
  view.up.fromArray(scene.up);
  const centre = new THREE.Vector3().fromArray(scene.centre);
  let intrinsics;  // fx, fy, cx, cy for the current canvas
  function fitCanvas() {
    if (startCamera) {
      width = startCamera.width, height = startCamera.height;
      intrinsics = [startCamera.fx, startCamera.fy, startCamera.cx, startCamera.cy];
    } else {
      width = Math.max(16, window.innerWidth), height = Math.max(16, window.innerHeight - 48);
      const c0 = cameras[0];  // camera 0's vertical field of view
      const f = c0.fy * height / c0.height;
      intrinsics = [f, f, (width - 1) / 2, (height - 1) / 2];
    }
    renderer.setSize(width, height, false);
    canvas.style.width = width + 'px';
    canvas.style.height = height + 'px';
  }
  fitCanvas();
  // Controls orbit about a target. OrbitControls aims the camera at its target when created and
  // on every user move, so it is created before the pose is set and its target is put on the
  // optical axis: a camera's own pose stays exact until the user moves the view.
  const controls = new OrbitControls(view, canvas);
  function setViewPose(c) {
    setPose(view, c.R, c.t);
    const axis = view.getWorldDirection(new THREE.Vector3());
    const along = centre.clone().sub(view.position).dot(axis);
    controls.target.copy(view.position).addScaledVector(axis, Math.max(along, 1e-6));
  }
  setViewPose(startCamera || cameras[0]);

  // Depth maps: one float layer per camera, each camera in the bottom-left W × H of its layer.
  const depthTarget = new THREE.WebGLArrayRenderTarget(
      scene.atlas.cellWidth, scene.atlas.cellHeight, cameras.length,
      { type: THREE.FloatType, format: THREE.RedFormat, depthBuffer: true });
  depthTarget.texture.minFilter = depthTarget.texture.magFilter = THREE.NearestFilter;
  const cameraData = cameraTexture(cameras);
  const depthMaterial = new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3,
    vertexShader: depthVertex,
    fragmentShader: depthFragment,
    uniforms: { uCameras: { value: cameraData }, uCamera: { value: 0 },
                uNearFar: { value: new THREE.Vector2() } },
    side: THREE.DoubleSide,
  });
  const blendMaterial = new THREE.ShaderMaterial({
    glslVersion: THREE.GLSL3,
    defines: { MAX_CAMERAS: cameras.length },
    vertexShader: blendVertex,
    fragmentShader: blendFragment,
    side: THREE.DoubleSide,
    uniforms: {
      uCameras: { value: cameraData },
      uAtlas: { value: null },
      uDepth: { value: depthTarget.texture },
      uCount: { value: cameras.length },
      uUseMask: { value: useMask >>> 0 },
      uViewCentre: { value: new THREE.Vector3() },
      uViewAxis: { value: new THREE.Vector3() },
      uDirection: { value: weights.direction === 'axis' ? 1 : 0 },
      uSharpness: { value: weights.sharpness },
      uTolerance: { value: weights.depthTolerance },
      uFallback: { value: weights.fallback === 'colour' ? 1 : 0 },
      uFallbackColour: { value: new THREE.Vector3(...weights.fallbackColour.map((v) => v / 255)) },
    },
  });
  const mesh = new THREE.Mesh(new THREE.BufferGeometry(), blendMaterial);
  mesh.frustumCulled = false;
  const world = new THREE.Scene();
  world.add(mesh);
  const depthMesh = new THREE.Mesh(mesh.geometry, depthMaterial);
  depthMesh.frustumCulled = false;
  const depthScene = new THREE.Scene();
  depthScene.add(depthMesh);
  const depthCamera = new THREE.Camera();  // unused by the depth shader's own projection

  // Frames: loaded on demand, a few kept; a frame's depth maps are drawn when it is shown.
  const cache = new Map();
  function requestFrame(n) {
    if (!cache.has(n)) cache.set(n, loadFrame(base, scene, n));
    return cache.get(n);
  }
  function trimCache(current) {
    for (const [n, promise] of cache)
      if (n < current - 2 || n > current + 6) {
        cache.delete(n);
        promise.then((f) => { f.geometry.dispose(); f.atlas.dispose(); }, () => {});
      }
  }
  let shown = null;
  function drawDepthMaps() {
    const r = scene.radius;
    cameras.forEach((c, i) => {
      const d = new THREE.Vector3().fromArray(cameraCentre(c.R, c.t)).distanceTo(centre);
      depthMaterial.uniforms.uCamera.value = i;
      depthMaterial.uniforms.uNearFar.value.set(Math.max(1e-4 * (d + r), d - 1.5 * r), d + 1.5 * r);
      depthTarget.viewport.set(0, 0, c.width, c.height);
      depthTarget.scissor.set(0, 0, c.width, c.height);
      renderer.setRenderTarget(depthTarget, i);
      renderer.setClearColor(0x000000, 0);
      renderer.clear(true, true, false);
      renderer.render(depthScene, depthCamera);
    });
    renderer.setRenderTarget(null);
    renderer.setClearColor(new THREE.Color(...scene.weights.background.map((v) => v / 255)), 0);
  }
  async function showFrame(n) {
    const frame = await requestFrame(n);
    if (shown !== frame) {
      mesh.geometry = depthMesh.geometry = frame.geometry;
      blendMaterial.uniforms.uAtlas.value = frame.atlas;
      drawDepthMaps();
      shown = frame;
    }
    api.frame = n;
    trimCache(n);
    for (let k = 1; k <= 3 && n + k < scene.frames.count; ++k) requestFrame(n + k);
    updateUi();
    draw();
  }

  function draw() {
    const d = view.position.distanceTo(centre), r = scene.radius;
    setIntrinsics(view, ...intrinsics, width, height, Math.max(1e-4 * (d + r), d - 1.5 * r),
                  d + 1.5 * r);
    blendMaterial.uniforms.uViewCentre.value.copy(view.position);
    view.getWorldDirection(blendMaterial.uniforms.uViewAxis.value);
    renderer.render(world, view);
  }

  controls.addEventListener('change', draw);

  // Playback: the next frame is shown once loaded and its time has come; seeking lands on GOM
  // starts, the stream's random-access points.
  const gomStarts = scene.gomStarts.length ? scene.gomStarts : [0];
  const slider = document.getElementById('seek');
  const playButton = document.getElementById('play');
  const label = document.getElementById('frame');
  slider.max = String(scene.frames.count - 1);
  function gomStartAtOrBefore(n) {
    let s = gomStarts[0];
    for (const g of gomStarts) if (g <= n) s = g;
    return s;
  }
  function updateUi() {
    slider.value = String(api.frame);
    playButton.textContent = api.playing ? 'Pause' : 'Play';
    const gom = gomStarts.filter((g) => g <= api.frame).length;
    label.textContent = `frame ${api.frame + 1}/${scene.frames.count} · GOM ${gom}/${gomStarts.length}`;
  }
  let busy = false, lastTick = 0;
  function tick(time) {
    if (api.playing && !busy && time - lastTick >= 1000 / scene.frames.rate) {
      lastTick = time;
      busy = true;
      showFrame((api.frame + 1) % scene.frames.count).catch(fail).finally(() => { busy = false; });
    }
    requestAnimationFrame(tick);
  }
  api.play = () => { api.playing = true; updateUi(); };
  api.pause = () => { api.playing = false; updateUi(); };
  api.setFrame = (n) => showFrame(Math.min(Math.max(0, n | 0), scene.frames.count - 1));
  api.seekGom = (n) => api.setFrame(gomStartAtOrBefore(n));
  api.viewFromCamera = (name) => {
    const c = cameras.find((x) => x.name === name);
    if (!c) throw new Error(`no camera named '${name}'`);
    setViewPose(c);
    draw();
  };
  api.orbit = (degrees) => {  // turn the view about the up axis through the centre
    const q = new THREE.Quaternion().setFromAxisAngle(view.up, degrees * Math.PI / 180);
    view.position.sub(centre).applyQuaternion(q).add(centre);
    view.quaternion.premultiply(q);
    view.updateMatrixWorld(true);
    controls.target.sub(centre).applyQuaternion(q).add(centre);
    draw();
  };
  api.capture = () => {
    draw();
    const gl = renderer.getContext();
    const pixels = new Uint8Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    const rows = new Uint8Array(pixels.length);  // GL rows start at the bottom
    for (let y = 0; y < height; ++y)
      rows.set(pixels.subarray((height - 1 - y) * width * 4, (height - y) * width * 4), y * width * 4);
    let text = '';
    for (let i = 0; i < rows.length; i += 0x8000)
      text += String.fromCharCode(...rows.subarray(i, i + 0x8000));
    return { width, height, rgba: btoa(text) };
  };
  playButton.addEventListener('click', () => (api.playing ? api.pause() : api.play()));
  slider.addEventListener('input', () => { api.seekGom(Number(slider.value)).catch(fail); });
  document.getElementById('prev-gom').addEventListener('click', () => {
    const i = gomStarts.lastIndexOf(gomStartAtOrBefore(api.frame));
    api.setFrame(gomStarts[Math.max(0, i - 1)]).catch(fail);
  });
  document.getElementById('next-gom').addEventListener('click', () => {
    const i = gomStarts.lastIndexOf(gomStartAtOrBefore(api.frame));
    api.setFrame(gomStarts[Math.min(gomStarts.length - 1, i + 1)]).catch(fail);
  });
  const cameraMenu = document.getElementById('camera');
  for (const c of cameras) cameraMenu.add(new Option(c.name, c.name));
  cameraMenu.addEventListener('change', () => {
    if (cameraMenu.value) api.viewFromCamera(cameraMenu.value);
  });
  window.addEventListener('keydown', (e) => {
    if (e.key === ' ') { api.playing ? api.pause() : api.play(); e.preventDefault(); }
    if (e.key === 'ArrowRight') document.getElementById('next-gom').click();
    if (e.key === 'ArrowLeft') document.getElementById('prev-gom').click();
  });
  window.addEventListener('resize', () => { if (!startCamera) { fitCanvas(); draw(); } });

  await api.setFrame(Number(params.get('frame') || 0));
  if (params.get('play') === '1') api.play();
  requestAnimationFrame(tick);
  statusLine.textContent = `${scene.description} · ${cameras.length} cameras · ` +
                           `weights: ${weights.direction}, k = ${weights.sharpness}`;
  api.state = 'ready';
}

main().catch(fail);
