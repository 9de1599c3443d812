// The browser tests' HTTP server (player.test.mjs, wasm.test.mjs): static files from a few
// folders on 127.0.0.1, with the HTTP Range requests (206 Partial Content) that 3dvo-play answers
// too, so that a page may read a stream in parts.
//
//   const server = await serve({ '': playerDir, wasm: wasmDir, streams: streamsDir });
//   server.url  -> 'http://127.0.0.1:<port>/'
//   await server.close();
//
// A request's first path segment picks the folder (the '' folder serves every other path; '/'
// is index.html there, or an empty page without one); '..' segments and missing files are 404.
//
// A download that stalls (for the page's progressive playback): serve(roots, { hold: {
// '/streams/x.3dvo': n } }) sends the first n bytes of that file at once and the rest only after
// server.release('/streams/x.3dvo').
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';

const types = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.json': 'application/json', '.png': 'image/png', '.wasm': 'application/wasm',
};

// [start, end] (inclusive) of a single-range header "bytes=a-b" / "bytes=a-" / "bytes=-n" over
// `size` bytes; null when absent or not of that form (the whole file is sent), 'unsatisfiable'
// when it lies past the end.
export function parseRange(header, size) {
  const m = /^bytes=(\d*)-(\d*)$/.exec(header || '');
  if (!m || (m[1] === '' && m[2] === '')) return null;
  let start, end;
  if (m[1] === '') {  // the last n bytes
    start = Math.max(0, size - Number(m[2]));
    end = size - 1;
  } else {
    start = Number(m[1]);
    end = m[2] === '' ? size - 1 : Math.min(Number(m[2]), size - 1);
  }
  if (start >= size || start > end) return 'unsatisfiable';
  return [start, end];
}

function fileFor(roots, url) {
  const parts = url.split('/').slice(1);
  if (parts.some((p) => p === '..')) return null;
  if (parts.length > 1 && parts[0] !== '' && roots[parts[0]] !== undefined)
    return path.join(roots[parts[0]], ...parts.slice(1));
  if (roots[''] === undefined) return null;
  return path.join(roots[''], ...(url === '/' ? ['index.html'] : parts));
}

export async function serve(roots, { hold = {} } = {}) {
  const released = {};
  for (const url of Object.keys(hold)) {
    let release;
    const promise = new Promise((resolve) => { release = resolve; });
    released[url] = { promise, release };
  }
  const server = http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    const file = fileFor(roots, url);
    fs.stat(file || '', (error, stat) => {
      if (error || !stat.isFile()) {
        if (url === '/') {
          response.writeHead(200, { 'Content-Type': 'text/html' });
          response.end('<!doctype html><title>3dvo test</title>');
        } else {
          response.writeHead(404, { 'Content-Type': 'text/plain' });
          response.end('not found');
        }
        return;
      }
      const headers = { 'Content-Type': types[path.extname(file)] || 'application/octet-stream',
                        'Accept-Ranges': 'bytes', 'Cache-Control': 'no-store' };
      const range = parseRange(request.headers.range, stat.size);
      if (range === 'unsatisfiable') {
        response.writeHead(416, { ...headers, 'Content-Range': `bytes */${stat.size}` });
        response.end();
        return;
      }
      const [start, end] = range || [0, stat.size - 1];
      headers['Content-Length'] = String(Math.max(0, end - start + 1));
      if (range) headers['Content-Range'] = `bytes ${start}-${end}/${stat.size}`;
      response.writeHead(range ? 206 : 200, headers);
      if (request.method === 'HEAD' || stat.size === 0) {
        response.end();
        return;
      }
      if (hold[url] !== undefined && !range && hold[url] < end) {
        fs.createReadStream(file, { start, end: hold[url] - 1 }).pipe(response, { end: false })
          .once('unpipe', () => released[url].promise.then(
              () => fs.createReadStream(file, { start: hold[url], end }).pipe(response)));
        return;
      }
      fs.createReadStream(file, { start, end }).pipe(response);
    });
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  return {
    url: `http://127.0.0.1:${server.address().port}/`,
    release: (url) => released[url].release(),
    close: () => new Promise((resolve) => {
      server.closeAllConnections();
      server.close(resolve);
    }),
  };
}
