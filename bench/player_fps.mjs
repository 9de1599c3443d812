// The web player's playback rate in headless Chromium on its software GL (SwiftShader): opens
// index.html?stream=...&play=1 (automatic camera path on, the window's size) and reports, after
// a warm-up, the frames shown per second against the stream's rate (each one drawn: depth
// passes, YUV conversion, view-dependent blend) and the frames the page decoded per second
// (docs/performance.md, "In the browser"). With --no-draw the page decodes and plays without
// drawing: what the decoding alone sustains in the page.
//
//   node bench/player_fps.mjs <stream.3dvo> [seconds, default 10] [WIDTHxHEIGHT, default 960x540]
//                             [--no-draw: the page decodes and plays without drawing (draw=0)]
//
// Environment: TDVO_PLAYER_DIR (the assembled player folder with wasm/, default build/player),
// TDVO_CHROMIUM (default /usr/bin/chromium). Run from the checkout's root.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const noDraw = process.argv.includes('--no-draw');
const [streamArg, secondsArg, sizeArg] = process.argv.slice(2).filter((a) => a !== '--no-draw');
if (!streamArg) {
  console.error('usage: node bench/player_fps.mjs <stream.3dvo> [seconds] [WIDTHxHEIGHT]');
  process.exit(2);
}
const stream = path.resolve(streamArg);
const seconds = Number(secondsArg || 10);
const [width, height] = (sizeArg || '960x540').split('x').map(Number);
const playerDir = path.resolve(process.env.TDVO_PLAYER_DIR || 'build/player');
const chromiumPath = process.env.TDVO_CHROMIUM || '/usr/bin/chromium';
if (!fs.existsSync(path.join(playerDir, 'wasm', 'tdvo_decoder.wasm'))) {
  console.error(`player_fps: ${playerDir}/wasm/ has no WebAssembly decoder (bash scripts/wasm.sh, ` +
                'then cmake --build build)');
  process.exit(1);
}
const load = (file) => import(pathToFileURL(path.join(playerDir, 'test', file)).href);
const { serve } = await load('serve.mjs');
const { launchChromium } = await load('support.mjs');

const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'tdvo-fps-'));
const server = await serve({ '': playerDir, streams: path.dirname(stream) });
const browser = await launchChromium(chromiumPath, profile);
try {
  const page = await browser.newPage();
  await page.setViewportSize({ width, height: height + 48 });  // the page's bar is 48 pixels
  await page.goto(`${server.url}index.html?stream=streams/${path.basename(stream)}&play=1` +
                  (noDraw ? '&draw=0' : ''));
  await page.waitForFunction(() => window.tdvoPlayer && window.tdvoPlayer.state !== 'loading',
                             null, { timeout: 60000 });
  const state = await page.evaluate(() => [window.tdvoPlayer.state, window.tdvoPlayer.error]);
  if (state[0] !== 'ready') throw new Error(`the player failed: ${state[1]}`);
  const sample = () => page.evaluate(() => {
    const t = window.tdvoPlayer.timing;
    return { now: performance.now(), drawn: t.render.framesDrawn, renderMs: t.render.renderMs,
             decoded: t.framesDecoded, geometryMs: t.geometryMs, rate: window.tdvoPlayer.info.frameRate,
             frames: window.tdvoPlayer.info.frameCount, cameras: window.tdvoPlayer.info.cameras.length };
  });
  await page.waitForTimeout(2000);  // warm-up: the first GOM, shader compilation
  const a = await sample();
  await page.waitForTimeout(seconds * 1000);
  const b = await sample();
  const wall = (b.now - a.now) / 1000, drawn = b.drawn - a.drawn;
  console.log(`${path.basename(stream)}: ${b.frames} frames at ${b.rate} fps, ${b.cameras} cameras, ` +
              `canvas ${noDraw ? 'not drawn' : `${width}x${height}`}, ${wall.toFixed(1)} s of playing`);
  if (!noDraw) console.log(`shown      ${(drawn / wall).toFixed(1)} frames/s (the stream's rate: ${b.rate})`);
  console.log(`decoded    ${((b.decoded - a.decoded) / wall).toFixed(1)} frames/s, geometry ` +
              `${((b.geometryMs - a.geometryMs) / Math.max(1, b.decoded - a.decoded)).toFixed(1)} ms per frame`);
} finally {
  await browser.close();
  await server.close();
  fs.rmSync(profile, { recursive: true, force: true });
}
