// Browser test of the web player (node --test; registered in ctest as player_browser_test).
//
// Makes a small synthetic rig with this build's 3dvo-synth, exports it with 3dvo-render, serves
// the player and the data from 127.0.0.1, and drives Debian's headless Chromium (SwiftShader
// WebGL 2, no GPU) through playwright-core. Checks that the page draws non-empty frames, plays,
// seeks to GOM starts, orbits, and that its frame at a camera's own pose, and at that pose with
// the camera left out, matches the CPU renderer inside the camera's mask.
//
// Environment: TDVO_BIN_DIR (the apps), TDVO_PLAYER_DIR (the assembled player folder, default:
// this file's parent folder), TDVO_CHROMIUM (default /usr/bin/chromium).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';

// Measured with Chromium 156 / SwiftShader (docs/rendering.md): 49.0 dB at the own pose, 45.2 dB
// with the camera left out. The bound leaves room for other GL implementations' rounding and
// coverage rules at silhouette pixels.
const MIN_PSNR_DB = 40;
const CAMERA = 'cam03';

const here = path.dirname(fileURLToPath(import.meta.url));
const playerDir = process.env.TDVO_PLAYER_DIR || path.dirname(here);
const binDir = process.env.TDVO_BIN_DIR;
const chromiumPath = process.env.TDVO_CHROMIUM || '/usr/bin/chromium';

let work, server, baseUrl, browser;  // browser: a persistent context with a fresh profile

function run(app, args) {
  execFileSync(path.join(binDir, app), args, { stdio: ['ignore', 'ignore', 'inherit'] });
}

function readPng(file) {
  return PNG.sync.read(fs.readFileSync(file));  // always RGBA 8-bit
}

// Static files: /data/... from the export, everything else from the player folder.
function serve(root, dataRoot) {
  const types = { '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json',
                  '.png': 'image/png', '.bin': 'application/octet-stream' };
  return http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    const file = url.startsWith('/data/') ? path.join(dataRoot, url.slice(6))
                                          : path.join(root, url === '/' ? 'index.html' : url);
    fs.readFile(file, (error, bytes) => {
      if (error) {
        response.writeHead(404);
        response.end();
        return;
      }
      response.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
      response.end(bytes);
    });
  });
}

before(async () => {
  assert.ok(binDir, 'TDVO_BIN_DIR must name the folder of 3dvo-synth and 3dvo-render');
  assert.ok(fs.existsSync(chromiumPath),
            `${chromiumPath} is missing: install Debian's chromium (scripts/packages.txt)`);
  work = fs.mkdtempSync(path.join(os.tmpdir(), 'tdvo-player-'));
  const synth = path.join(work, 'synth');
  run('3dvo-synth', ['-o', synth, '--FrameCount=4']);
  fs.writeFileSync(path.join(synth, 'gom_starts.txt'), '0 2\n');
  run('3dvo-render', ['-i', synth, '--Mode=export', '-o', path.join(work, 'export')]);
  run('3dvo-render', ['-i', synth, '--Path=camera', `--Camera=${CAMERA}`, '--FrameCount=1',
                      '-o', path.join(work, 'own')]);
  run('3dvo-render', ['-i', synth, '--Mode=leave-one-out', '--FrameCount=1', '--SaveRenders',
                      '-o', path.join(work, 'loo')]);
  server = serve(playerDir, path.join(work, 'export'));
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  baseUrl = `http://127.0.0.1:${server.address().port}/index.html`;
  browser = await chromium.launchPersistentContext(path.join(work, 'chromium-profile'), {
    executablePath: chromiumPath,
    headless: true,
    viewport: { width: 640, height: 480 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
});

after(async () => {
  if (browser) await browser.close();
  if (server) server.close();
  if (work) fs.rmSync(work, { recursive: true, force: true });
});

async function openPlayer(query) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${baseUrl}?data=/data/&${query}`);
  await page.waitForFunction(() => window.tdvoPlayer && window.tdvoPlayer.state !== 'loading',
                             null, { timeout: 30000 });
  const state = await page.evaluate(() => [window.tdvoPlayer.state, window.tdvoPlayer.error]);
  assert.deepEqual(state, ['ready', ''], `player failed: ${state[1]} ${errors.join('; ')}`);
  return page;
}

async function capture(page) {
  const c = await page.evaluate(() => window.tdvoPlayer.capture());
  return { width: c.width, height: c.height, data: Buffer.from(c.rgba, 'base64') };
}

// PSNR of the RGB channels over the mask pixels, and how many mask pixels the page left empty.
function compareInMask(test, reference, mask) {
  assert.equal(test.width, reference.width);
  assert.equal(test.height, reference.height);
  let sum = 0, count = 0, uncovered = 0;
  for (let i = 0; i < test.width * test.height; ++i) {
    if (mask.data[4 * i] < 128) continue;
    if (test.data[4 * i + 3] === 0) ++uncovered;
    for (let c = 0; c < 3; ++c) {
      const d = test.data[4 * i + c] - reference.data[4 * i + c];
      sum += d * d;
    }
    count += 3;
  }
  return { psnr: sum === 0 ? Infinity : 10 * Math.log10(255 * 255 * count / sum),
           pixels: count / 3, uncovered };
}

function objectPixels(image) {
  let n = 0;
  for (let i = 3; i < image.data.length; i += 4) if (image.data[i] !== 0) ++n;
  return n;
}

test('own pose matches the CPU renderer inside the mask', async () => {
  const page = await openPlayer(`camera=${CAMERA}`);
  const shot = await capture(page);
  const mask = readPng(path.join(work, 'synth', CAMERA, 'mask_0000.png'));
  const r = compareInMask(shot, readPng(path.join(work, 'own', '0000.png')), mask);
  console.log(`own pose: PSNR ${r.psnr.toFixed(2)} dB over ${r.pixels} mask pixels, ` +
              `${r.uncovered} not drawn`);
  assert.ok(r.psnr >= MIN_PSNR_DB, `PSNR ${r.psnr} dB < ${MIN_PSNR_DB} dB`);
  assert.ok(r.uncovered <= 0.01 * r.pixels, `${r.uncovered} mask pixels not drawn`);
  await page.close();
});

test('camera left out: the shader blend matches the CPU renderer', async () => {
  const page = await openPlayer(`camera=${CAMERA}&exclude=${CAMERA}`);
  const shot = await capture(page);
  const mask = readPng(path.join(work, 'synth', CAMERA, 'mask_0000.png'));
  const r = compareInMask(shot, readPng(path.join(work, 'loo', CAMERA, '0000.png')), mask);
  console.log(`leave-one-out: PSNR ${r.psnr.toFixed(2)} dB over ${r.pixels} mask pixels`);
  assert.ok(r.psnr >= MIN_PSNR_DB, `PSNR ${r.psnr} dB < ${MIN_PSNR_DB} dB`);
  // And it is a different picture from the own pose's (the camera's texture is really unused).
  const own = compareInMask(shot, readPng(path.join(work, 'own', '0000.png')), mask);
  assert.ok(own.psnr < r.psnr, 'the left-out camera seems to be used');
  await page.close();
});

test('draws non-empty frames, plays, orbits and seeks to GOM starts', async () => {
  const page = await openPlayer('');
  const first = await capture(page);
  assert.ok(objectPixels(first) > 1000, 'the first frame is (nearly) empty');
  const screenshot = PNG.sync.read(await page.screenshot());
  assert.ok(screenshot.width > 0 && screenshot.height > 0);

  await page.evaluate(() => window.tdvoPlayer.play());
  await page.waitForFunction(() => window.tdvoPlayer.frame >= 2, null, { timeout: 20000 });
  await page.evaluate(() => window.tdvoPlayer.pause());
  const playing = await capture(page);
  assert.ok(objectPixels(playing) > 1000, 'a played frame is (nearly) empty');
  assert.notDeepEqual(playing.data, first.data, 'playback does not change the picture');

  await page.evaluate(() => window.tdvoPlayer.orbit(60));
  const turned = await capture(page);
  assert.ok(objectPixels(turned) > 1000, 'the orbited view is (nearly) empty');
  assert.notDeepEqual(turned.data, playing.data, 'orbiting does not change the picture');

  // GOM starts are 0 and 2 (gom_starts.txt): seeking to frame 3 lands on 2, to 1 on 0.
  assert.equal(await page.evaluate(() => window.tdvoPlayer.seekGom(3).then(() => window.tdvoPlayer.frame)), 2);
  assert.equal(await page.evaluate(() => window.tdvoPlayer.seekGom(1).then(() => window.tdvoPlayer.frame)), 0);
  await page.close();
});
