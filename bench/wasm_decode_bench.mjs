// Geometry decoding speed of the WebAssembly decoder in headless Chromium next to the native
// 3dvo-dec, on one stream (docs/wasm.md, "Speed"). Both make every frame and its geometry MD5
// line; the best of several runs is reported.
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

// Native: wall time of 3dvo-dec printing the MD5 lines (no output files).
let nativeBest = Infinity;
let nativeLines = [];
for (let i = 0; i < runs; ++i) {
  const t0 = process.hrtime.bigint();
  const r = spawnSync(path.join(binDir, '3dvo-dec'), ['-i', stream], { encoding: 'utf8' });
  const seconds = Number(process.hrtime.bigint() - t0) / 1e9;
  if (r.status !== 0) throw new Error(`3dvo-dec failed: ${r.stderr}`);
  nativeLines = r.stdout.split('\n').filter((l) => / geometry=/.test(l));
  nativeBest = Math.min(nativeBest, seconds);
}

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
  return { best, lines, vertexFrames, userAgent: navigator.userAgent };
}, runs);
await browser.close();
server.close();

const same = JSON.stringify(result.lines) === JSON.stringify(nativeLines);
const frames = result.lines.length;
const row = (name, seconds) =>
  `${name.padEnd(8)} ${seconds.toFixed(3).padStart(8)} s  ${(frames / seconds).toFixed(1).padStart(8)} frames/s  ` +
  `${(result.vertexFrames / seconds / 1e6).toFixed(2).padStart(7)} M vertex-frames/s`;
console.log(`${path.basename(stream)}: ${frames} frames, ${result.vertexFrames} vertex-frames, ` +
            `best of ${runs}; MD5 lines ${same ? 'identical' : 'DIFFER'}`);
console.log(row('native', nativeBest));
console.log(row('wasm', result.best));
console.log(`wasm / native speed: ${(nativeBest / result.best).toFixed(2)}  (${result.userAgent})`);
process.exit(same ? 0 : 1);
