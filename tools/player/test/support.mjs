// What the browser tests share (player.test.mjs, wasm.test.mjs): the WebAssembly module's
// folder or SKIP, headless Chromium, and 3dvo-dec's error line for a stream.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

export const SKIP = 77;  // ctest's SKIP_RETURN_CODE

// The WebAssembly build's folder (TDVO_WASM_DIR, default <TDVO_SOURCE_DIR>/build-wasm); without
// the module, says so and exits with SKIP.
export function requireWasm() {
  const source = process.env.TDVO_SOURCE_DIR;
  const dir = process.env.TDVO_WASM_DIR || (source && path.join(source, 'build-wasm'));
  for (const file of ['tdvo_decoder.js', 'tdvo_decoder.wasm']) {
    if (!dir || !fs.existsSync(path.join(dir, file))) {
      console.log(`SKIP: ${path.join(dir || '<TDVO_WASM_DIR>', file)} is missing: the ` +
                  'WebAssembly decoder is not built (bash scripts/wasm.sh builds it; docs/wasm.md)');
      process.exit(SKIP);
    }
  }
  return dir;
}

// Debian's Chromium, headless, WebGL 2 on SwiftShader (no GPU), a fresh profile in `profile`.
export async function launchChromium(executablePath, profile) {
  if (!fs.existsSync(executablePath))
    throw new Error(`${executablePath} is missing: install Debian's chromium (scripts/packages.txt)`);
  const { chromium } = await import('playwright-core');
  return chromium.launchPersistentContext(profile, {
    executablePath,
    headless: true,
    viewport: { width: 640, height: 480 },
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
}

// What 3dvo-dec prints after "3dvo-dec: error: " for `file` (run in its folder, so that the
// stream is named as the page names it); '' when it decodes.
export function nativeError(binDir, file) {
  const r = spawnSync(path.join(binDir, '3dvo-dec'), ['-i', path.basename(file)],
                      { cwd: path.dirname(file), encoding: 'utf8' });
  const prefix = '3dvo-dec: error: ';
  const line = r.stderr.split('\n').find((l) => l.startsWith(prefix));
  return line ? line.slice(prefix.length) : '';
}
