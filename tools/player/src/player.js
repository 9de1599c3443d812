// The 3DVO web player: plays a .3dvo stream itself. Bytes come from a streaming fetch (or a
// local file); the geometry is decoded by the project's WebAssembly decoder (./wasm/, docs/wasm.md),
// each camera's texture by the browser's H.264 decoder (WebCodecs, src/textures.js), and the
// frame is drawn with the view-dependent texture weights of the CPU renderer, computed per
// fragment (src/shaders.js). Playing starts once the first GOM has arrived. docs/rendering.md,
// "The web player".
//
// URL parameters (all optional):
//   stream=URL        the .3dvo to play (else: drop a file on the page or choose one)
//   camera=NAME       start at this camera's pose and intrinsics, the canvas at its size
//   frame=N           start at stream frame N (from 0; decoded from the GOM start before it)
//   play=1            start playing
//   path=0            no automatic camera path
//   blending=angle|ulr, direction=ray|axis, sharpness=K, resolution=B, edgewidth=E, tolerance=T,
//   fallback=fill|nearest|colour
//                     weighting options (3dvo-render's Blending, ViewDirection, Sharpness,
//                     ResolutionPenalty, EdgeWidth, DepthTolerance, Fallback; defaults as
//                     tools/render/view_renderer.h RenderOptions)
//   exclude=NAME,...  cameras whose textures are not used (leave-one-out views)
//   md5=1             hash every decoded frame as 3dvo-dec does (md5Lines()) and play the stream
//                     once through as fast as it decodes
//   draw=0            decode and play without drawing (a bench of decoding: bench/player_fps.mjs)
//   gpu=MiB           GPU memory the textures may take (default 1024): depth maps at the
//                     cameras' size, the boxes' planes; over it the page plays untextured
//
// window.tdvoPlayer is the page's test interface: state ('loading' | 'ready' | 'error'), error,
// info (the stream's), frame (stream frame index), playing, setFrame(n), seekGom(n), play(),
// pause(), viewFromCamera(name), orbit(degrees), capture() → {width, height, rgba: base64},
// md5Lines(), timing.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { cameraCentre, setIntrinsics, setPose } from './camera_math.js';
import { blendFragment, blendVertex, convertFragment, convertVertex, depthFragment, depthVertex,
         edgeFragment, edgeRowFragment, fillFragment, pullFragment, pushFragment }
  from './shaders.js';
import { FrameStream, INTERRUPTED, readInto } from './stream.js';
import { upDirection, ViewPath } from './view_path.js';

const params = new URLSearchParams(window.location.search);
const api = { state: 'loading', error: '', frame: 0, playing: false, info: null,
              md5Lines: () => [], timing: {} };
window.tdvoPlayer = api;

const statusLine = document.getElementById('status');
function fail(error) {
  const message = error instanceof Error ? error.message : String(error);
  if (api.state === 'error') return;  // the first error is the one to show
  api.state = 'error';
  api.error = message;
  statusLine.textContent = 'error: ' + message;
  statusLine.classList.add('error');
  console.error(message);
}

// The module, or one clear error.
async function loadDecoder() {
  const url = new URL('wasm/tdvo_decoder.js', document.baseURI).href;
  let create;
  try {
    create = (await import(url)).default;
  } catch (e) {
    throw new Error(`the WebAssembly decoder (${url}) cannot be loaded: ${e.message}`);
  }
  return create();
}

// Per-camera parameters as a float texture (layout in src/shaders.js).
function cameraTexture(cameras, excluded) {
  const data = new Float32Array(Math.max(1, cameras.length) * 8 * 4);
  cameras.forEach((c, i) => {
    const o = i * 32;
    for (let r = 0; r < 3; ++r) data.set([...c.R.slice(3 * r, 3 * r + 3), c.t[r]], o + 4 * r);
    data.set([c.fx, c.fy, c.cx, c.cy], o + 12);
    data.set(c.distortion.slice(0, 4), o + 16);
    data.set([c.distortion[4], c.width, c.height, excluded.has(c.name) ? 0 : 1], o + 20);
    data.set([c.box.x, c.box.y, c.box.width, c.box.height], o + 24);
    data.set([...cameraCentre(rows(c.R), c.t), 0], o + 28);
  });
  const texture = new THREE.DataTexture(data, 8, Math.max(1, cameras.length), THREE.RGBAFormat,
                                        THREE.FloatType);
  texture.minFilter = texture.magFilter = THREE.NearestFilter;
  texture.needsUpdate = true;
  return texture;
}

function rows(R) { return [R.slice(0, 3), R.slice(3, 6), R.slice(6, 9)]; }

// The GPU memory the page may take for a stream's textures (gpu=MiB, default 1024): per camera
// a float depth map at the camera's size with its depth buffer, and the texture box as Y, U, V
// planes and RGB.
const gpuBudgetMiB = Number(params.get('gpu') || 1024);

// '' when this GPU holds what the cameras need (texture sizes, array layers, the budget above);
// else what is missing, in one line. A stream's header may declare 64 cameras of 16384 × 16384
// (the decoder refuses a camera larger than the stream's size allows, MaxTexturePixelsPerByte,
// but 64 cameras within it can still ask for gigabytes): that must not become the allocations.
function gpuLimitsProblem(renderer, cameras) {
  const gl = renderer.getContext();
  const maxSide = gl.getParameter(gl.MAX_TEXTURE_SIZE);
  const maxLayers = gl.getParameter(gl.MAX_ARRAY_TEXTURE_LAYERS);
  const w = Math.max(...cameras.map((c) => c.width)), h = Math.max(...cameras.map((c) => c.height));
  const bw = Math.max(...cameras.map((c) => c.box.width));
  const bh = Math.max(...cameras.map((c) => c.box.height));
  if (Math.max(w, h, bw, bh) > maxSide)
    return `the cameras' ${w}x${h} images exceed this GPU's ${maxSide}-pixel textures`;
  if (cameras.length > maxLayers)
    return `${cameras.length} cameras exceed this GPU's ${maxLayers} texture layers`;
  const bytes = cameras.length * (w * h * 8 + bw * bh * (1.5 + 4));
  if (!(bytes <= gpuBudgetMiB * 2 ** 20))
    return `the ${cameras.length} cameras of ${w}x${h} need ${Math.ceil(bytes / 2 ** 20)} MiB of ` +
           `GPU memory, more than the page's ${gpuBudgetMiB} MiB (gpu=)`;
  return '';
}

// One plane of every camera's box as a single-channel array texture, a layer per camera.
function planeTexture(width, height, layers) {
  const t = new THREE.DataArrayTexture(new Uint8Array(width * height * layers), width, height, layers);
  t.format = THREE.RedFormat;
  t.type = THREE.UnsignedByteType;
  t.minFilter = t.magFilter = THREE.NearestFilter;
  t.generateMipmaps = false;
  t.unpackAlignment = 1;
  t.needsUpdate = true;
  return t;
}

// The stream's source from the URL, or from a file the user drops or chooses.
function chooseSource() {
  if (params.has('stream')) {
    const url = params.get('stream');
    const name = decodeURIComponent(new URL(url, document.baseURI).pathname.split('/').pop());
    return Promise.resolve({ url, name: name || url });
  }
  statusLine.textContent = 'drop a .3dvo file on the page, or choose one';
  const input = document.getElementById('file');
  input.hidden = false;
  return new Promise((resolve) => {
    const take = (file) => { if (file) { input.hidden = true; resolve({ file, name: file.name }); } };
    input.addEventListener('change', () => take(input.files[0]));
    window.addEventListener('dragover', (e) => e.preventDefault());
    window.addEventListener('drop', (e) => { e.preventDefault(); take(e.dataTransfer.files[0]); });
  });
}

async function main() {
  const canvas = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer(
      { canvas, antialias: false, alpha: true, preserveDrawingBuffer: true });
  if (!renderer.capabilities.isWebGL2) throw new Error('this browser has no WebGL 2');
  const tdvo = await loadDecoder();
  const source = await chooseSource();
  const stream = new FrameStream(tdvo, source.name, { md5: params.get('md5') === '1' });
  api.md5Lines = () => stream.md5Lines();
  api.timing = stream.timing;
  let progress = '';
  // The status line: the name and progress until the stream is open, then more.
  let showStatus = () => { statusLine.textContent = `${source.name}: ${progress}`; };
  const reading = readInto(source, source.name, stream, (received, total) => {
    progress = total ? `received ${received} of ${total} bytes` : `received ${received} bytes`;
    if (api.state !== 'error') showStatus();
  });
  reading.catch((e) => stream.fail(e));
  statusLine.textContent = `${source.name}: waiting for the stream`;
  const info = await stream.open();
  api.info = info;
  const first = stream.firstGeometry;  // its textures are still on their way
  if (!first) throw new Error(`${source.name}: the stream has no frames`);

  const cameras = info.cameras;
  let textured = cameras.length > 0 && stream.videos !== null;
  const gpuProblem = textured ? gpuLimitsProblem(renderer, cameras) : '';
  if (gpuProblem) {
    stream.dropTextures(gpuProblem + ': playing without textures');
    textured = false;
  }
  const weights = { blending: 'ulr', direction: 'axis', sharpness: 4, resolutionPenalty: 1,
                    edgeWidth: 8, depthTolerance: 0.01, fallback: 'fill',
                    fallbackColour: [128, 128, 128], background: [0, 0, 0] };
  if (params.has('blending')) weights.blending = params.get('blending');
  if (params.has('resolution')) weights.resolutionPenalty = Number(params.get('resolution'));
  if (params.has('edgewidth')) weights.edgeWidth = Math.min(16, Math.max(0, Number(params.get('edgewidth'))));
  if (params.has('direction')) weights.direction = params.get('direction');
  if (params.has('sharpness')) weights.sharpness = Number(params.get('sharpness'));
  if (params.has('tolerance')) weights.depthTolerance = Number(params.get('tolerance'));
  if (params.has('fallback')) weights.fallback = params.get('fallback');
  const excluded = new Set((params.get('exclude') || '').split(',').filter((s) => s));
  for (const name of excluded)
    if (!cameras.some((c) => c.name === name)) throw new Error(`exclude: no camera named '${name}' in the stream`);

  // The object: centre of the first frame's bounding box (as the CPU renderer's orbit), and a
  // sphere around the grid's cube, which holds every frame (near and far planes).
  const firstGeometry = new THREE.BufferGeometry();
  firstGeometry.setAttribute('position', new THREE.BufferAttribute(first.positions, 3));
  firstGeometry.computeBoundingBox();
  const centre = firstGeometry.boundingBox.getCenter(new THREE.Vector3());
  const side = info.grid.step * (2 ** info.grid.bits - 1);
  const gridCentre = new THREE.Vector3(...info.grid.origin).addScalar(side / 2);
  const radius = Math.sqrt(3) / 2 * side + gridCentre.distanceTo(centre);

  const start = params.get('camera');
  const startCamera = start ? cameras.find((c) => c.name === start) : null;
  if (start && !startCamera) throw new Error(`no camera named '${start}' in the stream`);
  renderer.setPixelRatio(1);
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;  // colours written as computed
  const background = new THREE.Color(...weights.background.map((v) => v / 255));
  renderer.setClearColor(background, 0);
  let width, height;
  const view = new THREE.PerspectiveCamera();
  const up = upDirection(info) || new THREE.Vector3(0, 1, 0);
  view.up.copy(up);
  let intrinsics;  // fx, fy, cx, cy for the current canvas
  function fitCanvas() {
    if (startCamera) {
      width = startCamera.width, height = startCamera.height;
      intrinsics = [startCamera.fx, startCamera.fy, startCamera.cx, startCamera.cy];
    } else {
      width = Math.max(16, window.innerWidth), height = Math.max(16, window.innerHeight - 48);
      // camera 0's vertical field of view, or 40 degrees without cameras
      const f = cameras.length ? cameras[0].fy * height / cameras[0].height
                               : height / 2 / Math.tan(THREE.MathUtils.degToRad(20));
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
    setPose(view, rows(c.R), c.t);
    const axis = view.getWorldDirection(new THREE.Vector3());
    const along = centre.clone().sub(view.position).dot(axis);
    controls.target.copy(view.position).addScaledVector(axis, Math.max(along, 1e-6));
  }
  if (startCamera || cameras.length) {
    setViewPose(startCamera || cameras[0]);
  } else {  // framing the object: from the front (+z), a little above
    const r = firstGeometry.boundingBox.getSize(new THREE.Vector3()).length() / 2;
    const f = intrinsics[1] / height;  // 1 / (2 tan(fov / 2))
    view.position.copy(centre).add(new THREE.Vector3(0, 0.35, 1).normalize()
                                       .multiplyScalar(1.2 * r * 2 * f + r));
    controls.target.copy(centre);
    view.lookAt(centre);
    view.updateMatrixWorld(true);
  }
  firstGeometry.dispose();

  // Materials: the view-dependent blend of the decoded textures, or flat shading.
  const world = new THREE.Scene();
  const mesh = new THREE.Mesh(new THREE.BufferGeometry());
  mesh.frustumCulled = false;
  world.add(mesh);
  let drawDepthMaps = () => {}, showPictures = () => {};
  // Flat shading: a geometry-only stream, a browser without WebCodecs, and the first frame
  // until its textures are decoded.
  const flatMaterial = new THREE.MeshLambertMaterial({ color: 0xc8c8c8, flatShading: true,
                                                      side: THREE.DoubleSide });
  mesh.material = flatMaterial;
  world.add(new THREE.AmbientLight(0xffffff, 0.35));
  const light = new THREE.DirectionalLight(0xffffff, 2.2);
  light.position.set(0.3, 0.6, 1);  // a headlight, a little above and right of the view
  view.add(light);
  world.add(view);
  let blendMaterial = null;
  let drawFilled = null;  // Fallback=fill: draws the view through the push-pull passes
  if (textured) {
    const depthTarget = new THREE.WebGLArrayRenderTarget(
        Math.max(...cameras.map((c) => c.width)), Math.max(...cameras.map((c) => c.height)),
        cameras.length, { type: THREE.FloatType, format: THREE.RedFormat, depthBuffer: true });
    depthTarget.texture.minFilter = depthTarget.texture.magFilter = THREE.NearestFilter;
    const edgeTargets = [0, 1].map(() => {
      const t = new THREE.WebGLArrayRenderTarget(depthTarget.width, depthTarget.height, cameras.length,
                                                 { type: THREE.FloatType, format: THREE.RedFormat,
                                                   depthBuffer: false });
      t.texture.minFilter = t.texture.magFilter = THREE.NearestFilter;
      t.texture.generateMipmaps = false;
      return t;
    });
    const cameraData = cameraTexture(cameras, excluded);
    const depthMaterial = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: depthVertex,
      fragmentShader: depthFragment,
      uniforms: { uCameras: { value: cameraData }, uCamera: { value: 0 },
                  uNearFar: { value: new THREE.Vector2() } },
      side: THREE.DoubleSide,
    });
    const boxW = Math.max(...cameras.map((c) => c.box.width));
    const boxH = Math.max(...cameras.map((c) => c.box.height));
    const planes = [planeTexture(boxW, boxH, cameras.length),
                    planeTexture(boxW / 2, boxH / 2, cameras.length),
                    planeTexture(boxW / 2, boxH / 2, cameras.length)];
    const rgbTarget = new THREE.WebGLArrayRenderTarget(boxW, boxH, cameras.length,
                                                       { depthBuffer: false });
    rgbTarget.texture.minFilter = rgbTarget.texture.magFilter = THREE.NearestFilter;
    rgbTarget.texture.generateMipmaps = false;
    const convertMaterial = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: convertVertex,
      fragmentShader: convertFragment,
      uniforms: { uY: { value: planes[0] }, uU: { value: planes[1] }, uV: { value: planes[2] },
                  uLayer: { value: 0 }, uSize: { value: new THREE.Vector2() } },
      depthTest: false,
      depthWrite: false,
    });
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), convertMaterial);
    quad.frustumCulled = false;
    const convertScene = new THREE.Scene();
    convertScene.add(quad);
    blendMaterial = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      defines: { MAX_CAMERAS: cameras.length },
      vertexShader: blendVertex,
      fragmentShader: blendFragment,
      side: THREE.DoubleSide,
      uniforms: {
        uCameras: { value: cameraData },
        uRgb: { value: rgbTarget.texture },
        uDepth: { value: depthTarget.texture },
        uEdge: { value: edgeTargets[1].texture },
        uBlending: { value: weights.blending === 'ulr' ? 1 : 0 },
        uResolutionPenalty: { value: weights.resolutionPenalty },
        uEdgeWidth: { value: weights.edgeWidth },
        uViewFocal: { value: 1 },
        uCount: { value: cameras.length },
        uViewCentre: { value: new THREE.Vector3() },
        uViewAxis: { value: new THREE.Vector3() },
        uDirection: { value: weights.direction === 'axis' ? 1 : 0 },
        uSharpness: { value: weights.sharpness },
        uTolerance: { value: weights.depthTolerance },
        uFallback: { value: { nearest: 0, colour: 1, fill: 2 }[weights.fallback] ?? 2 },
        uFallbackColour: { value: new THREE.Vector3(...weights.fallbackColour.map((v) => v / 255)) },
      },
    });
    if (weights.fallback === 'fill') drawFilled = fillPasses(renderer, weights.fallbackColour);
    const depthMesh = new THREE.Mesh(mesh.geometry, depthMaterial);
    depthMesh.frustumCulled = false;
    const depthScene = new THREE.Scene();
    depthScene.add(depthMesh);
    const depthCamera = new THREE.Camera();  // unused by the depth shader's own projection
    // Blending=ulr: the edge distance maps from the depth maps (src/shaders.js edgeRowFragment).
    const edgeUniforms = { uLayer: { value: 0 }, uSize: { value: new THREE.Vector2() },
                           uRadius: { value: Math.ceil(weights.edgeWidth) },
                           uEdgeWidth: { value: weights.edgeWidth } };
    const edgePasses = [
      [edgeRowFragment, { uDepth: { value: depthTarget.texture } }],
      [edgeFragment, { uRows: { value: edgeTargets[0].texture } }],
    ].map(([fragmentShader, own]) => {
      const material = new THREE.ShaderMaterial({
        glslVersion: THREE.GLSL3, vertexShader: convertVertex, fragmentShader,
        uniforms: { ...edgeUniforms, ...own }, depthTest: false, depthWrite: false });
      const pass = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
      pass.frustumCulled = false;
      const scene = new THREE.Scene();
      scene.add(pass);
      return scene;
    });
    const drawEdgeMaps = () => {
      edgePasses.forEach((scene, k) => {
        cameras.forEach((c, i) => {
          edgeUniforms.uLayer.value = i;
          edgeUniforms.uSize.value.set(c.width, c.height);
          edgeTargets[k].viewport.set(0, 0, c.width, c.height);
          edgeTargets[k].scissor.set(0, 0, c.width, c.height);
          renderer.setRenderTarget(edgeTargets[k], i);
          renderer.render(scene, depthCamera);
        });
      });
      renderer.setRenderTarget(null);
    };
    drawDepthMaps = () => {
      depthMesh.geometry = mesh.geometry;
      cameras.forEach((c, i) => {
        const d = new THREE.Vector3().fromArray(cameraCentre(rows(c.R), c.t)).distanceTo(centre);
        depthMaterial.uniforms.uCamera.value = i;
        depthMaterial.uniforms.uNearFar.value.set(Math.max(1e-4 * (d + radius), d - 1.5 * radius),
                                                  d + 1.5 * radius);
        depthTarget.viewport.set(0, 0, c.width, c.height);
        depthTarget.scissor.set(0, 0, c.width, c.height);
        renderer.setRenderTarget(depthTarget, i);
        renderer.setClearColor(0x000000, 0);
        renderer.clear(true, true, false);
        renderer.render(depthScene, depthCamera);
      });
      renderer.setRenderTarget(null);
      renderer.setClearColor(background, 0);
      if (weights.blending === 'ulr' && weights.edgeWidth > 0) drawEdgeMaps();
    };
    // Each camera's planes into its layer (rows of the box, top row first).
    showPictures = (pictures) => {
      cameras.forEach((c, i) => {
        const p = pictures[i], w = c.box.width, h = c.box.height;
        const sizes = [[w, h, 0], [w / 2, h / 2, w * h], [w / 2, h / 2, w * h * 5 / 4]];
        sizes.forEach(([pw, ph, offset], k) => {
          const t = planes[k], tw = t.image.width;
          for (let y = 0; y < ph; ++y)
            t.image.data.set(p.subarray(offset + y * pw, offset + (y + 1) * pw), (i * t.image.height + y) * tw);
          t.addLayerUpdate(i);
          t.needsUpdate = true;
        });
      });
      cameras.forEach((c, i) => {  // YUV -> RGB, once per frame
        convertMaterial.uniforms.uLayer.value = i;
        convertMaterial.uniforms.uSize.value.set(c.box.width, c.box.height);
        rgbTarget.viewport.set(0, 0, c.box.width, c.box.height);
        rgbTarget.scissor.set(0, 0, c.box.width, c.box.height);
        renderer.setRenderTarget(rgbTarget, i);
        renderer.render(convertScene, depthCamera);
      });
      renderer.setRenderTarget(null);
    };
  }

  function draw() {
    const t0 = performance.now();
    const d = view.position.distanceTo(centre);
    setIntrinsics(view, ...intrinsics, width, height, Math.max(1e-4 * (d + radius), d - 1.5 * radius),
                  d + 1.5 * radius);
    if (mesh.material === blendMaterial) {
      blendMaterial.uniforms.uViewCentre.value.copy(view.position);
      blendMaterial.uniforms.uViewFocal.value = intrinsics[0];
      view.getWorldDirection(blendMaterial.uniforms.uViewAxis.value);
    }
    if (mesh.material === blendMaterial && drawFilled) drawFilled(world, view, width, height);
    else renderer.render(world, view);
    renderTiming.framesDrawn++;
    renderTiming.renderMs += performance.now() - t0;
  }
  const renderTiming = { framesDrawn: 0, renderMs: 0 };
  api.timing = Object.assign(stream.timing, { render: renderTiming });

  const drawing = params.get('draw') !== '0';
  function show(frame) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(frame.positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(frame.triangles, 1));
    mesh.geometry.dispose();
    mesh.geometry = geometry;
    api.frame = frame.index;
    updateUi();
    if (!drawing) return;
    if (textured && frame.pictures) {
      showPictures(frame.pictures);
      drawDepthMaps();
      mesh.material = blendMaterial;
    }
    // The automatic path moves with the frames (no extra draws: software GL is slow).
    if (api.playing && pathOn) path.apply(view, controls.target, performance.now() / 1000);
    draw();
  }

  // Playback: frames come from the stream in order at its frame rate (with md5=1 as fast as
  // they decode); after the last one it starts over at the first GOM. Seeking lands on GOM
  // starts; a start not yet arrived waits for it ("buffering").
  const md5Run = params.get('md5') === '1';
  const count = info.frameCount;
  const slider = document.getElementById('seek');
  const playButton = document.getElementById('play');
  const label = document.getElementById('frame');
  slider.max = String(count - 1);
  let buffering = false;
  showStatus = () => {
    const parts = [source.name];
    if (info.description) parts.push(info.description);
    parts.push(cameras.length ? `${cameras.length} cameras` : 'geometry only');
    if (textured) parts.push(`weights: ${weights.blending}, ${weights.direction}, k = ${weights.sharpness}`);
    if (progress) parts.push(progress);
    if (buffering) parts.push('buffering');
    statusLine.textContent = parts.join(' · ');
    if (stream.textureNote) statusLine.textContent += '\n' + stream.textureNote;
  };
  const gomIndices = () => stream.gomStarts().map((s) => s - info.firstFrame);
  function gomStartAtOrBefore(n) {
    let s = 0;
    for (const g of gomIndices()) if (g <= n) s = g;
    return s;
  }
  function updateUi() {
    slider.value = String(api.frame);
    playButton.textContent = api.playing ? 'Pause' : 'Play';
    const starts = gomIndices();
    const gom = starts.filter((g) => g <= api.frame).length;
    label.textContent = `frame ${api.frame + 1}/${count} · GOM ${gom}/${starts.length}` +
                        (stream.finished ? '' : '+');
  }
  // One job at a time: the next frame, or a seek; `busy` is the job running.
  let busy = null;
  function job(f) {
    const run = (busy || Promise.resolve()).then(f);
    busy = run.catch(fail);
    return run;
  }
  async function advance() {
    let frame = await stream.next();
    if (frame === INTERRUPTED) return;  // a seek came: it shows its frame
    if (!frame) {  // past the last frame: from the start again
      if (md5Run) { api.pause(); return; }
      await stream.seek(0, setBuffering);
      frame = await stream.next();
    }
    if (frame && frame !== INTERRUPTED) show(frame);
  }
  function setBuffering(on) { buffering = on; showStatus(); }
  // Shows frame n exactly: from the GOM start at or before it, decoding forward.
  async function showExactly(n) {
    const s = await stream.seek(n, setBuffering);
    let frame = null;
    for (let i = s; i <= n; ++i) {
      frame = await stream.next();
      if (frame === INTERRUPTED) return;  // a later seek: it shows its frame
    }
    if (frame) show(frame);
  }
  let pathOn = params.get('path') !== '0' && cameras.length > 1 && !md5Run;
  const path = cameras.length > 1 ? new ViewPath(cameras, centre, up) : null;
  controls.addEventListener('start', () => { pathOn = false; });
  controls.addEventListener('change', draw);
  // Frame k is due at the start time + k periods, whatever the display's refresh rate; a page
  // that falls behind shows the next frame at once rather than catching up in a burst.
  let due = 0, pending = false;
  const period = 1000 / info.frameRate;
  function tick(time) {
    if (api.state === 'error') return;
    if (api.playing && !pending && (md5Run || time >= due)) {
      due = Math.max(due + period, time - period / 2);
      pending = true;
      job(advance).finally(() => { pending = false; });
    }
    requestAnimationFrame(tick);
  }
  api.play = () => { api.playing = true; if (path) path.restart(); updateUi(); };
  api.pause = () => { api.playing = false; updateUi(); };
  // A seek calls off the decodes queued before it (playback waiting for bytes, say) at once,
  // then runs as the next job.
  api.setFrame = (n) => {
    stream.interrupt();
    return job(() => showExactly(Math.min(Math.max(0, n | 0), count - 1)));
  };
  api.seekGom = (n) => {
    stream.interrupt();
    return job(async () => {
      const s = await stream.seek(Math.min(Math.max(0, n | 0), count - 1), setBuffering);
      const frame = await stream.next();
      if (frame && frame !== INTERRUPTED) show(frame);
      return s;
    });
  };
  api.viewFromCamera = (name) => {
    const c = cameras.find((x) => x.name === name);
    if (!c) throw new Error(`no camera named '${name}'`);
    pathOn = false;
    setViewPose(c);
    draw();
  };
  api.orbit = (degrees) => {  // turn the view about the up axis through the centre
    pathOn = false;
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
    const flipped = new Uint8Array(pixels.length);  // GL rows start at the bottom
    for (let y = 0; y < height; ++y)
      flipped.set(pixels.subarray((height - 1 - y) * width * 4, (height - y) * width * 4), y * width * 4);
    let text = '';
    for (let i = 0; i < flipped.length; i += 0x8000)
      text += String.fromCharCode(...flipped.subarray(i, i + 0x8000));
    return { width, height, rgba: btoa(text) };
  };
  playButton.addEventListener('click', () => (api.playing ? api.pause() : api.play()));
  slider.addEventListener('input', () => { api.seekGom(Number(slider.value)); });
  document.getElementById('prev-gom').addEventListener('click', () => {
    const starts = gomIndices(), i = starts.lastIndexOf(gomStartAtOrBefore(api.frame));
    api.seekGom(starts[Math.max(0, i - 1)]);
  });
  document.getElementById('next-gom').addEventListener('click', () => {
    const starts = gomIndices(), i = starts.lastIndexOf(gomStartAtOrBefore(api.frame));
    api.seekGom(i + 1 < starts.length ? starts[i + 1] : count);  // past the last: buffering
  });
  const cameraMenu = document.getElementById('camera');
  for (const c of cameras) cameraMenu.add(new Option(c.name, c.name));
  cameraMenu.hidden = cameras.length === 0;
  cameraMenu.addEventListener('change', () => {
    if (cameraMenu.value) api.viewFromCamera(cameraMenu.value);
  });
  window.addEventListener('keydown', (e) => {
    if (e.key === ' ') { api.playing ? api.pause() : api.play(); e.preventDefault(); }
    if (e.key === 'ArrowRight') document.getElementById('next-gom').click();
    if (e.key === 'ArrowLeft') document.getElementById('prev-gom').click();
  });
  window.addEventListener('resize', () => { if (!startCamera) { fitCanvas(); draw(); } });

  show(first);  // its geometry at once
  showStatus();
  const startFrame = Number(params.get('frame') || 0);
  if (startFrame > 0) await api.setFrame(startFrame);
  else show(await stream.next());  // with its textures
  api.state = 'ready';
  if (params.get('play') === '1' || md5Run) api.play();
  requestAnimationFrame(tick);
}

main().catch(fail);

// Fallback=fill in the page (src/shaders.js pushFragment): the view is drawn into a frame target,
// reduced level by level to 1 × 1 and pulled back up; the last pass writes the canvas. Targets
// follow the canvas size.
function fillPasses(renderer, flatColour) {
  const uniforms = {
    uFine: { value: null }, uCoarse: { value: null }, uFineSize: { value: new THREE.Vector2() },
    uCoarseSize: { value: new THREE.Vector2() }, uFineIsFrame: { value: false },
    uFlat: { value: new THREE.Vector3(...flatColour.map((v) => v / 255)) }, uTop: { value: false },
  };
  const scenes = [pushFragment, pullFragment, fillFragment].map((fragmentShader) => {
    const material = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3, vertexShader: convertVertex, fragmentShader, uniforms,
      depthTest: false, depthWrite: false });
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material);
    quad.frustumCulled = false;
    const scene = new THREE.Scene();
    scene.add(quad);
    return scene;
  });
  const passCamera = new THREE.Camera();
  let frame = null, levels = [];  // levels[l - 1]: { size, down, pulled } of level l
  const target = (w, h, type) => {
    const t = new THREE.WebGLRenderTarget(w, h, { type, depthBuffer: type === THREE.UnsignedByteType });
    t.texture.minFilter = t.texture.magFilter = THREE.NearestFilter;
    t.texture.generateMipmaps = false;
    return t;
  };
  const pass = (scene, output, fine, fineSize, fineIsFrame, coarse, coarseSize, top) => {
    uniforms.uFine.value = fine.texture;
    uniforms.uFineSize.value.set(...fineSize);
    uniforms.uFineIsFrame.value = fineIsFrame;
    uniforms.uCoarse.value = coarse ? coarse.texture : fine.texture;
    uniforms.uCoarseSize.value.set(...(coarseSize || fineSize));
    uniforms.uTop.value = top;
    renderer.setRenderTarget(output);
    renderer.render(scene, passCamera);
  };
  return (world, view, width, height) => {
    if (!frame || frame.width !== width || frame.height !== height) {
      if (frame) frame.dispose();
      levels.forEach((l) => { l.down.dispose(); l.pulled.dispose(); });
      frame = target(width, height, THREE.UnsignedByteType);
      levels = [];
      for (let w = width, h = height; w > 1 || h > 1;) {
        w = (w + 1) >> 1, h = (h + 1) >> 1;
        levels.push({ size: [w, h], down: target(w, h, THREE.FloatType), pulled: target(w, h, THREE.FloatType) });
      }
    }
    renderer.setRenderTarget(frame);
    renderer.clear(true, true, false);
    renderer.render(world, view);
    if (levels.length === 0) {  // a 1 × 1 canvas: nothing to fill from
      renderer.setRenderTarget(null);
      renderer.render(world, view);
      return;
    }
    levels.forEach((l, i) => {
      const finer = i === 0 ? { t: frame, size: [width, height] } : { t: levels[i - 1].down, size: levels[i - 1].size };
      pass(scenes[0], l.down, finer.t, finer.size, i === 0, null, null, false);
    });
    for (let i = levels.length - 1; i >= 0; --i) {
      const top = i === levels.length - 1;
      pass(scenes[1], levels[i].pulled, levels[i].down, levels[i].size, false,
           top ? null : levels[i + 1].pulled, top ? null : levels[i + 1].size, top);
    }
    renderer.setRenderTarget(null);
    renderer.clear(true, true, false);
    pass(scenes[2], null, frame, [width, height], true, levels[0].pulled, levels[0].size, false);
  };
}
