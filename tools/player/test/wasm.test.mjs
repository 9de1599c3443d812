// Browser test of the WebAssembly decoder (docs/wasm.md; node --test, registered in ctest as
// wasm_browser_test).
//
// Serves the module (scripts/wasm.sh's build-wasm/tdvo_decoder.{js,wasm}) and the conformance
// streams from 127.0.0.1 and decodes each stream in Debian's headless Chromium through
// playwright-core: every frame's geometry MD5 line must equal the stream's .md5 log, and a
// truncated and a corrupted stream must give exactly the message 3dvo-dec prints after
// "3dvo-dec: error: ".
//
// Environment: TDVO_WASM_DIR (the wasm build, default <source>/build-wasm), TDVO_SOURCE_DIR (the
// checkout), TDVO_BIN_DIR (3dvo-dec), TDVO_CHROMIUM (default /usr/bin/chromium). Without the
// module the test says so and exits with 77 (ctest's SKIP_RETURN_CODE): run scripts/wasm.sh.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

const sourceDir = process.env.TDVO_SOURCE_DIR;
const wasmDir = process.env.TDVO_WASM_DIR || (sourceDir && path.join(sourceDir, 'build-wasm'));
const binDir = process.env.TDVO_BIN_DIR;
const chromiumPath = process.env.TDVO_CHROMIUM || '/usr/bin/chromium';
const SKIP = 77;

if (!sourceDir || !binDir) {
  console.error('wasm_browser_test: TDVO_SOURCE_DIR and TDVO_BIN_DIR must be set');
  process.exit(1);
}
for (const file of ['tdvo_decoder.js', 'tdvo_decoder.wasm']) {
  if (!fs.existsSync(path.join(wasmDir, file))) {
    console.log(`SKIP: ${path.join(wasmDir, file)} is missing: the WebAssembly decoder is not ` +
                `built (bash scripts/wasm.sh builds it; docs/wasm.md)`);
    process.exit(SKIP);
  }
}

const { chromium } = await import('playwright-core');
const streamsDir = path.join(sourceDir, 'conformance', 'streams');
const streams = fs.readdirSync(streamsDir).filter((f) => f.endsWith('.3dvo')).sort();
let work, server, baseUrl, browser, page;

// /wasm/... from the wasm build, /streams/... from the conformance streams, /bad/... from the
// test's own folder; / is an empty page.
function serve() {
  const types = { '.js': 'text/javascript', '.wasm': 'application/wasm', '.html': 'text/html' };
  const roots = { wasm: wasmDir, streams: streamsDir, bad: work };
  return http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    const [, root, ...rest] = url.split('/');
    if (url === '/') {
      response.writeHead(200, { 'Content-Type': 'text/html' });
      response.end('<!doctype html><title>tdvo wasm</title>');
      return;
    }
    if (!roots[root] || rest.some((p) => p === '..')) {
      response.writeHead(404);
      response.end();
      return;
    }
    const file = path.join(roots[root], ...rest);
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

// What 3dvo-dec prints for `file` (run in its folder, named as in the browser).
function nativeDecode(file) {
  const r = spawnSync(path.join(binDir, '3dvo-dec'), ['-i', path.basename(file)],
                      { cwd: path.dirname(file), encoding: 'utf8' });
  const prefix = '3dvo-dec: error: ';
  const errorLine = r.stderr.split('\n').find((l) => l.startsWith(prefix));
  return { status: r.status, error: errorLine ? errorLine.slice(prefix.length) : '' };
}

before(async () => {
  assert.ok(fs.existsSync(chromiumPath),
            `${chromiumPath} is missing: install Debian's chromium (scripts/packages.txt)`);
  work = fs.mkdtempSync(path.join(os.tmpdir(), 'tdvo-wasm-'));
  server = serve();
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  baseUrl = `http://127.0.0.1:${server.address().port}/`;
  browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  page = await browser.newPage();
  await page.goto(baseUrl);
});

after(async () => {
  if (browser) await browser.close();
  if (server) server.close();
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
    const native = nativeDecode(file);
    assert.notEqual(native.status, 0, `${name}: 3dvo-dec accepted it`);
    assert.notEqual(native.error, '', `${name}: 3dvo-dec printed no error line`);
    const got = await decodeInBrowser(`/bad/${name}`, name);
    assert.equal(got.error, native.error, name);
  }
});
