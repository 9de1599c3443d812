// Decoding speed of the WebAssembly decoder in headless Chromium next to the native 3dvo-dec,
// on one stream (docs/wasm.md, "Speed"; docs/performance.md, "In the browser"). Both make every
// frame and its geometry MD5 line; the best of several runs is reported. For a textured stream
// the browser also decodes every camera's pictures as the player does: the access units the
// module hands out into WebCodecs' VideoDecoder, each picture's planes copied out
// (VideoFrame.copyTo, I420); the native figure beside it is 3dvo-dec with textures (H.264 with
// FFmpeg, shapes, MD5 of the planes; no output files).
//
//   node bench/wasm_decode_bench.mjs <stream.3dvo> [runs]
//
// Environment: TDVO_WASM_DIR (default build-wasm), TDVO_BIN_DIR (3dvo-dec, default build/bin),
// TDVO_PLAYER_DIR (a folder whose node_modules has playwright-core, default build/player),
// TDVO_CHROMIUM (default /usr/bin/chromium). Run from the checkout's root.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import { createRequire } from 'node:module';
import path from 'node:path';

const [streamArg, runsArg] = process.argv.slice(2);
if (!streamArg) {
  console.error('usage: node bench/wasm_decode_bench.mjs <stream.3dvo> [runs]');
  process.exit(2);
}
const stream = path.resolve(streamArg);
const runs = Number(runsArg || 5);
const wasmDir = path.resolve(process.env.TDVO_WASM_DIR || 'build-wasm');
const binDir = path.resolve(process.env.TDVO_BIN_DIR || 'build/bin');
const playerDir = path.resolve(process.env.TDVO_PLAYER_DIR || 'build/player');
const chromiumPath = process.env.TDVO_CHROMIUM || '/usr/bin/chromium';
const { chromium } = createRequire(path.join(playerDir, 'package.json'))('playwright-core');

// Native: wall time of 3dvo-dec printing the MD5 lines (no output files), on one thread; for a
// textured stream that includes the textures (3dvo-dec has no geometry-only mode: compare
// geometry speed on geometry-only streams).
function nativeRun(args) {
  let best = Infinity, lines = [];
  for (let i = 0; i < runs; ++i) {
    const t0 = process.hrtime.bigint();
    const r = spawnSync(path.join(binDir, '3dvo-dec'), ['-i', stream, ...args], { encoding: 'utf8' });
    const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
    if (r.status !== 0) throw new Error(`3dvo-dec failed: ${r.stderr}`);
    lines = r.stdout.split('\n').filter((l) => l.startsWith('MD5 frame='));
    best = Math.min(best, seconds);
  }
  return { best, lines };
}
const native = nativeRun(['--Threads=1']);
const nativeLines = native.lines.filter((l) => / geometry=/.test(l));
const textured = native.lines.length > nativeLines.length;

const server = http.createServer((request, response) => {
  const url = new URL(request.url, 'http://x').pathname;
  const files = { '/tdvo_decoder.js': path.join(wasmDir, 'tdvo_decoder.js'),
                  '/tdvo_decoder.wasm': path.join(wasmDir, 'tdvo_decoder.wasm'),
                  '/stream.3dvo': stream };
  if (url === '/') {
    response.writeHead(200, { 'Content-Type': 'text/html' });
    response.end('<!doctype html><title>bench</title>');
  } else if (files[url]) {
    const type = { '.js': 'text/javascript', '.wasm': 'application/wasm' }[path.extname(url)];
    response.writeHead(200, { 'Content-Type': type || 'application/octet-stream' });
    response.end(fs.readFileSync(files[url]));
  } else {
    response.writeHead(404);
    response.end();
  }
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const browser = await chromium.launch({ executablePath: chromiumPath, headless: true,
                                        args: ['--headless', '--no-sandbox', '--disable-gpu'] });
const page = await browser.newPage();
await page.goto(`http://127.0.0.1:${server.address().port}/`);
const result = await page.evaluate(async (runs) => {
  const { default: createTdvoDecoder } = await import('/tdvo_decoder.js');
  const module = await createTdvoDecoder();
  const bytes = new Uint8Array(await (await fetch('/stream.3dvo')).arrayBuffer());
  let best = Infinity, lines = [], vertexFrames = 0;
  for (let i = 0; i < runs; ++i) {
    const t0 = performance.now();
    const decoder = new module.Decoder(bytes, 'stream');
    const got = [];
    let vf = 0;
    while (decoder.next()) {
      got.push(decoder.geometryHashLine());
      vf += decoder.vertexCount();
    }
    decoder.delete();
    best = Math.min(best, (performance.now() - t0) / 1000);
    lines = got;
    vertexFrames = vf;
  }
  // Geometry and every camera's pictures, as the player decodes them.
  const codecOf = (unit) => {  // 'avc1.PPCCLL' from the SPS (NAL type 7)
    for (let i = 0; i + 4 < unit.length; ++i)
      if (unit[i] === 0 && unit[i + 1] === 0 && unit[i + 2] === 1 && (unit[i + 3] & 31) === 7)
        return 'avc1.' + [...unit.subarray(i + 4, i + 7)].map((b) => b.toString(16).padStart(2, '0')).join('');
    return null;
  };
  const isKey = (unit) => {  // an IDR slice (NAL type 5)
    for (let i = 0; i + 3 < unit.length; ++i)
      if (unit[i] === 0 && unit[i + 1] === 0 && unit[i + 2] === 1 && (unit[i + 3] & 31) === 5) return true;
    return false;
  };
  let textureBest = null, texturePictures = 0, textureLines = [];
  const probe = new module.Decoder(bytes, 'stream');
  const cameras = probe.info().cameras.length;
  probe.delete();
  if (cameras > 0 && typeof VideoDecoder === 'undefined') return { error: 'no WebCodecs VideoDecoder' };
  for (let i = 0; cameras > 0 && i < runs; ++i) {
    const t0 = performance.now();
    const decoder = new module.Decoder(bytes, 'stream');
    decoder.setTextureUnits(true);
    const boxes = decoder.info().cameras.map((c) => c.box);
    let pictures = 0, failure = null;
    const lines = [];
    const pending = boxes.map(() => []);  // frame numbers of the pictures not yet output
    const copies = [];
    const videoDecoders = boxes.map((box, c) => new VideoDecoder({
      output: (frame) => {
        const number = pending[c].shift();
        // Software-decoded H.264 pictures are I420 already: their planes, tightly packed.
        if (frame.format !== 'I420') failure = `camera ${c}: pictures in ${frame.format}, not I420`;
        const planes = new Uint8Array(frame.allocationSize());
        copies.push(frame.copyTo(planes).then(() => {
          ++pictures;
          if (i === 0) lines.push([number, c, decoder.textureHashLine(number, c, planes)]);
        }).finally(() => frame.close()));
      },
      error: (e) => { failure = String(e); },
    }));
    let timestamp = 0;
    while (decoder.next()) {
      for (let c = 0; c < boxes.length; ++c) {
        for (const unit of decoder.textureUnits(c)) {
          if (videoDecoders[c].state === 'unconfigured')
            videoDecoders[c].configure({ codec: codecOf(unit), codedWidth: boxes[c].width,
                                         codedHeight: boxes[c].height, optimizeForLatency: true });
          videoDecoders[c].decode(new EncodedVideoChunk(
              { type: isKey(unit) ? 'key' : 'delta', timestamp: timestamp, data: unit.slice() }));
          pending[c].push(decoder.frameNumber());
        }
      }
      timestamp += 40000;
    }
    try {
      await Promise.all(videoDecoders.map((v) => v.flush()));
      await Promise.all(copies);
    } catch (e) {
      failure = failure || String(e);
    }
    videoDecoders.forEach((v) => { if (v.state !== 'closed') v.close(); });
    decoder.delete();
    if (failure) return { error: failure };
    textureBest = Math.min(textureBest ?? Infinity, (performance.now() - t0) / 1000);
    texturePictures = pictures;
    if (i === 0) textureLines = lines;
  }
  return { best, lines, vertexFrames, textureBest, texturePictures, textureLines,
           userAgent: navigator.userAgent };
}, runs);
await browser.close();
server.close();

if (result.error) {
  console.error(`wasm_decode_bench: ${result.error}`);
  process.exit(1);
}
const same = JSON.stringify(result.lines) === JSON.stringify(nativeLines);
const frames = result.lines.length;
const row = (name, seconds) =>
  `${name.padEnd(8)} ${seconds.toFixed(3).padStart(8)} s  ${(frames / seconds).toFixed(1).padStart(8)} frames/s  ` +
  `${(result.vertexFrames / seconds / 1e6).toFixed(2).padStart(7)} M vertex-frames/s`;
console.log(`${path.basename(stream)}: ${frames} frames, ${result.vertexFrames} vertex-frames, ` +
            `best of ${runs}; MD5 lines ${same ? 'identical' : 'DIFFER'}`);
if (!textured) console.log(row('native', native.best));
console.log(row('wasm', result.best) + (textured ? '  (geometry only; texture units read, not decoded)' : ''));
if (!textured)
  console.log(`wasm / native speed: ${(native.best / result.best).toFixed(2)}  (${result.userAgent})`);
let texturesSame = true;
if (textured) {
  // The browser's texture lines in 3dvo-dec's order (per frame, cameras in order).
  const browserTextures = result.textureLines.sort((a, b) => a[0] - b[0] || a[1] - b[1]).map((l) => l[2]);
  const nativeTextures = native.lines.filter((l) => / texture /.test(l));
  texturesSame = JSON.stringify(browserTextures) === JSON.stringify(nativeTextures);
  const cameras = result.texturePictures / frames;
  console.log(`with textures (${cameras} cameras, ${result.texturePictures} pictures): texture MD5 ` +
              `lines ${texturesSame ? 'identical' : 'DIFFER'}`);
  const textureRow = (name, seconds) =>
    `${name.padEnd(8)} ${seconds.toFixed(3).padStart(8)} s  ${(frames / seconds).toFixed(1).padStart(8)} frames/s  ` +
    `${(seconds / frames * 1000).toFixed(2).padStart(7)} ms per frame`;
  console.log(textureRow('native', native.best));
  console.log(textureRow('browser', result.textureBest));
  console.log(`browser / native speed: ${(native.best / result.textureBest).toFixed(2)}  (${result.userAgent})`);
}
process.exit(same && texturesSame ? 0 : 1);
