// Browser test of the WebAssembly decoder (docs/wasm.md; node --test, registered in ctest as
// wasm_browser_test).
//
// Serves the module (scripts/wasm.sh's build-wasm/tdvo_decoder.{js,wasm}), the player and the
// conformance streams from 127.0.0.1 and decodes each stream in Debian's headless Chromium
// through playwright-core: every frame's geometry MD5 line must equal the stream's .md5 log; the
// player page (index.html?md5=1, WebCodecs for the textures) must give the whole log, texture
// and header lines included; and a truncated and a corrupted stream must give exactly the
// message 3dvo-dec prints after "3dvo-dec: error: ".
//
// Environment: TDVO_WASM_DIR (the wasm build, default <source>/build-wasm), TDVO_SOURCE_DIR (the
// checkout), TDVO_BIN_DIR (3dvo-dec), TDVO_PLAYER_DIR (the player folder, default: this file's
// parent folder), TDVO_CHROMIUM (default /usr/bin/chromium). Without the module the test says so
// and exits with 77 (ctest's SKIP_RETURN_CODE): run scripts/wasm.sh.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { fileURLToPath } from 'node:url';

import { serve } from './serve.mjs';
import { launchChromium, nativeError, requireWasm } from './support.mjs';

const sourceDir = process.env.TDVO_SOURCE_DIR;
const binDir = process.env.TDVO_BIN_DIR;
const chromiumPath = process.env.TDVO_CHROMIUM || '/usr/bin/chromium';
const playerDir = process.env.TDVO_PLAYER_DIR || path.dirname(path.dirname(fileURLToPath(import.meta.url)));

if (!sourceDir || !binDir) {
  console.error('wasm_browser_test: TDVO_SOURCE_DIR and TDVO_BIN_DIR must be set');
  process.exit(1);
}
const wasmDir = requireWasm();
const streamsDir = path.join(sourceDir, 'conformance', 'streams');
const streams = fs.readdirSync(streamsDir).filter((f) => f.endsWith('.3dvo')).sort();
let work, server, browser, page;

// Decodes /<url> in the page under `name`: { lines: the geometry MD5 lines, error: the message }.
async function decodeInBrowser(url, name) {
  return page.evaluate(async ([url, name]) => {
    const { default: createTdvoDecoder } = await import('/wasm/tdvo_decoder.js');
    window.tdvoModule = window.tdvoModule || await createTdvoDecoder();
    const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
    const lines = [];
    let decoder = null;
    try {
      decoder = new window.tdvoModule.Decoder(bytes, name);
      while (decoder.next()) lines.push(decoder.geometryHashLine());
      return { lines, error: '' };
    } catch (e) {
      return { lines, error: e instanceof Error ? e.message : `not an Error: ${e}` };
    } finally {
      if (decoder) decoder.delete();
    }
  }, [url, name]);
}

before(async () => {
  work = fs.mkdtempSync(path.join(os.tmpdir(), 'tdvo-wasm-'));
  server = await serve({ '': playerDir, wasm: wasmDir, streams: streamsDir, bad: work });
  browser = await launchChromium(chromiumPath, path.join(work, 'chromium-profile'));
  page = await browser.newPage();
  await page.goto(`${server.url}index.html`);  // the player without a stream: waits for a file
});

after(async () => {
  if (browser) await browser.close();
  if (server) await server.close();
  if (work) fs.rmSync(work, { recursive: true, force: true });
});

test('every conformance stream: the browser gives the geometry MD5 lines of its log', async () => {
  assert.ok(streams.length > 0, `no streams in ${streamsDir}`);
  for (const stream of streams) {
    const log = fs.readFileSync(path.join(streamsDir, stream.replace(/\.3dvo$/, '.md5')), 'utf8');
    const expected = log.split('\n').filter((l) => / geometry=/.test(l));
    const got = await decodeInBrowser(`/streams/${stream}`, stream);
    assert.equal(got.error, '', `${stream}: ${got.error}`);
    assert.ok(expected.length > 0, `${stream}: no geometry lines in its log`);
    assert.deepEqual(got.lines, expected, stream);
  }
});

test('info, GOM starts and seek', async () => {
  const stream = 'd3dmc_reuse_g3_ra2.3dvo';
  const got = await page.evaluate(async (url) => {
    const bytes = new Uint8Array(await (await fetch(url)).arrayBuffer());
    const decoder = new window.tdvoModule.Decoder(bytes, 'stream');
    try {
      const info = decoder.info();
      const starts = decoder.gomStarts();
      const all = [];
      let shapeOk = true;
      while (decoder.next()) {
        all.push(decoder.geometryHashLine());
        shapeOk &&= decoder.positions().length === 3 * decoder.vertexCount() &&
                    decoder.gridPositions().length === 3 * decoder.vertexCount() &&
                    decoder.triangles().length === 3 * decoder.triangleCount();
      }
      const last = starts[starts.length - 1];
      decoder.seek(last);
      const afterSeek = [];
      while (decoder.next()) afterSeek.push(decoder.geometryHashLine());
      let seekError = '';
      try {
        decoder.seek(info.firstFrame + info.frameCount + 5);
      } catch (e) {
        seekError = e.message;
      }
      return { info, starts, all, afterSeek, last, shapeOk, seekError };
    } finally {
      decoder.delete();
    }
  }, `/streams/${stream}`);
  assert.equal(got.all.length, got.info.frameCount);
  assert.ok(got.starts.length >= 1 && got.starts[0] === got.info.firstFrame);
  assert.ok(got.shapeOk, 'array lengths match the vertex and triangle counts');
  assert.deepEqual(got.afterSeek, got.all.slice(got.last - got.info.firstFrame));
  assert.notEqual(got.seekError, '', 'a seek past the end is an error');
});

test('truncated and corrupted streams give 3dvo-dec\'s error message', async () => {
  const bytes = fs.readFileSync(path.join(streamsDir, 'd3dmc_lossless_g8.3dvo'));
  const cases = {
    'truncated.3dvo': bytes.subarray(0, Math.floor(bytes.length * 0.45)),
    'corrupted.3dvo': Buffer.from(bytes),
    'header-only.3dvo': bytes.subarray(0, 20),
    'empty.3dvo': Buffer.alloc(0),
  };
  cases['corrupted.3dvo'][Math.floor(bytes.length * 0.6)] ^= 0x20;
  for (const [name, data] of Object.entries(cases)) {
    const file = path.join(work, name);
    fs.writeFileSync(file, data);
    const native = nativeError(binDir, file);
    assert.notEqual(native, '', `${name}: 3dvo-dec printed no error line`);
    const got = await decodeInBrowser(`/bad/${name}`, name);
    assert.equal(got.error, native, name);
  }
});

// The player page decodes each stream as it plays it (geometry with the module, textures with
// WebCodecs) and hashes every frame: md5Lines() is the whole log, as 3dvo-dec --verify compares.
test('every conformance stream: the player page gives its whole MD5 log', async () => {
  for (const stream of streams) {
    const expected = fs.readFileSync(path.join(streamsDir, stream.replace(/\.3dvo$/, '.md5')), 'utf8')
                       .split('\n').filter((l) => l.startsWith('MD5 '));
    const player = await browser.newPage();
    await player.goto(`${server.url}index.html?stream=streams/${stream}&md5=1`);
    await player.waitForFunction(() => window.tdvoPlayer && (window.tdvoPlayer.state === 'error' ||
        window.tdvoPlayer.md5Lines().some((l) => l.startsWith('MD5 header='))), null, { timeout: 60000 });
    const [state, error, lines, note] = await player.evaluate(() => {
      const p = window.tdvoPlayer;
      return [p.state, p.error, p.md5Lines(), document.getElementById('status').textContent];
    });
    assert.deepEqual([state, error], ['ready', ''], stream);
    assert.ok(!/without textures/.test(note), `${stream}: ${note}`);
    assert.deepEqual(lines, expected, stream);
    await player.close();
  }
});
