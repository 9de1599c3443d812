// A .3dvo stream as decoded frames: bytes arrive from a streaming fetch (or a local file) into
// the WebAssembly decoder's growing input; frames are decoded in order a few ahead of the one
// shown, geometry by the WebAssembly decoder and each camera's texture by WebCodecs
// (src/textures.js). docs/rendering.md, "The web player".
import { CameraVideo, codecString, isIdr, webCodecsProblem } from './textures.js';

const AHEAD = 4;  // frames decoded ahead of the one shown (bounded memory)

// What next() gives for a frame whose decoding a seek called off.
export const INTERRUPTED = Symbol('interrupted');

// Reads `source` ({url} or {file}) into the decoder, calling progress(received, total) per chunk
// (total: null when unknown). A missing file is an error worded as 3dvo-dec words it.
export async function readInto(source, name, stream, progress) {
  let body, total = null;
  if (source.file) {
    body = source.file.stream();
    total = source.file.size;
  } else {
    let response;
    try {
      response = await fetch(source.url);
    } catch (e) {
      throw new Error(`${name}: cannot open: ${e.message}`);
    }
    if (!response.ok)
      throw new Error(`${name}: cannot open: HTTP ${response.status} ${response.statusText}`.trim());
    const length = response.headers.get('Content-Length');
    if (length !== null && !response.headers.get('Content-Encoding')) total = Number(length);
    body = response.body;
  }
  const reader = body.getReader();
  let received = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    received += value.length;
    stream.append(value);
    progress(received, total);
  }
  stream.finish();
  progress(received, received);
}

// The decoded stream. Every decoder call runs in one promise chain (`work`), so that seeks and
// decodes never interleave; frames are {index, number, positions, triangles, gomStart,
// pictures: null | [per camera I420 planes]}. A decode waiting for bytes does not hold up a
// seek: interrupt() (which seek() calls) makes the waiting decodes give INTERRUPTED instead.
export class FrameStream {
  constructor(tdvo, name, { md5 = false } = {}) {
    this.tdvo = tdvo;
    this.decoder = tdvo.Decoder.growing(name);
    this.md5 = md5 ? { geometry: [], texture: [], gomStart: [] } : null;
    this.finished = false;
    this.failure = null;
    this.waiters = [];
    this.work = Promise.resolve();
    this.queue = [];
    this.generation = 0;  // advanced by interrupt(): decodes of an older one are called off
    this.videos = null;
    this.textureNote = '';
    this.timing = { framesDecoded: 0, geometryMs: 0, textureMs: 0, firstAt: 0, lastAt: 0 };
  }

  // Bytes in (from readInto), or a reading error.
  append(chunk) { this.decoder.append(chunk); this.wake(); }
  finish() { this.decoder.finish(); this.finished = true; this.wake(); }
  fail(error) { this.failure = error; this.wake(); }
  wake() { for (const w of this.waiters.splice(0)) w(); }

  // Waits until `ready()` (called after every arrival) is true; a reading error rejects.
  async until(ready) {
    for (;;) {
      if (this.failure) throw this.failure;
      if (ready()) return;
      await new Promise((resolve) => this.waiters.push(resolve));
    }
  }

  // Waits for the sequence header and the first frame's geometry; returns the stream info.
  // firstGeometry is then that frame without its textures (null: no frames). Sets up the
  // texture decoders (textureNote: '' or why the page plays without textures).
  async open() {
    await this.until(() => this.decoder.headerReady());
    this.info = this.decoder.info();
    if (this.info.cameras.length) this.decoder.setTextureUnits(true);
    await this.until(() => this.decoder.canDecodeNext());
    this.firstGeometry = null;
    if (!this.decoder.next()) return this.info;
    if (this.info.cameras.length) {
      // The first texture access unit's SPS names the codec.
      const codec = codecString(this.decoder.textureUnit(0));
      this.textureNote = codec ? await webCodecsProblem(codec)
                               : 'the first texture access unit has no SPS: playing without textures';
      if (!this.textureNote) {
        this.videos = this.info.cameras.map(
            (c) => new CameraVideo(codec, c.box, (e) => { this.textureFailure = e; }));
      }
    }
    this.pending = this.takeFrame();
    this.pending.catch(() => {});
    return this.info;
  }

  // Plays on without textures (`note` says why): the texture decoders are closed.
  dropTextures(note) {
    if (this.videos) for (const v of this.videos) v.close();
    this.videos = null;
    this.textureNote = note;
  }

  // The decoder's current frame, copied out of the module's memory, its textures on their way.
  takeFrame() {
    const d = this.decoder, start = performance.now();
    const frame = { index: d.frameIndex(), number: d.frameNumber(),
                    positions: d.positions().slice(), triangles: d.triangles().slice(),
                    gomStart: false, pictures: null };
    if (!this.firstGeometry) this.firstGeometry = frame;
    if (this.md5) this.md5.geometry[frame.index] = d.geometryHashLine();
    let pictures = Promise.resolve(null);
    if (this.info.cameras.length) {
      const units = this.info.cameras.map((_, c) => d.textureUnit(c).slice());
      frame.gomStart = isIdr(units[0]);
      if (this.md5) this.md5.gomStart[frame.index] = frame.gomStart;
      if (this.videos) {
        const timestamp = Math.round(frame.index * 1e6 / this.info.frameRate);
        pictures = Promise.all(this.videos.map((v, c) => v.decode(units[c], frame.gomStart, timestamp)));
      }
    }
    const geometryDone = performance.now();
    this.timing.geometryMs += geometryDone - start;
    return pictures.then((planes) => {
      if (this.textureFailure) throw this.textureFailure;
      this.timing.textureMs += performance.now() - geometryDone;
      if (planes && planes.every((p) => p)) {
        frame.pictures = planes;
        if (this.md5) {
          this.md5.texture[frame.index] = planes.map(
              (p, c) => this.decoder.textureHashLine(frame.number, c, p));
        }
      }
      const t = this.timing;
      t.lastAt = performance.now();
      if (!t.framesDecoded++) t.firstAt = t.lastAt;
      return frame;
    });
  }

  // The next frame in decode order (null after the last; INTERRUPTED when a seek called it
  // off), decoding up to AHEAD frames ahead.
  next() {
    while (this.queue.length < AHEAD) {
      // The chain waits for the geometry only: the job's result is wrapped in an array, which
      // a promise chain does not unwrap, so textures of several frames decode at once.
      const generation = this.generation;
      this.queue.push(this.schedule(() => this.decodeNext(generation)).then(([frame]) => frame));
    }
    return this.queue.shift();
  }

  // Calls off the decodes queued so far (those waiting for bytes give INTERRUPTED at once), so
  // that a seek need not wait for bytes the frames before it would have needed.
  interrupt() {
    ++this.generation;
    for (const f of this.queue.splice(0)) f.catch(() => {});
    this.wake();
  }

  schedule(job) {
    const result = this.work.then(job);
    this.work = result.then(() => {}, () => {});
    return result;
  }

  async decodeNext(generation) {
    if (generation !== this.generation) return [INTERRUPTED];
    if (this.pending !== undefined) {  // the frame open() decoded
      const frame = this.pending;
      this.pending = undefined;
      return [frame];
    }
    await this.until(() => generation !== this.generation || this.decoder.canDecodeNext());
    if (generation !== this.generation) return [INTERRUPTED];
    if (!this.decoder.next()) {  // the end: out with the pictures a decoder still holds
      if (this.videos) await Promise.all(this.videos.map((v) => v.flush()));
      return [null];
    }
    return [this.takeFrame()];
  }

  // Random access points (frame numbers) among the GOMs arrived so far.
  gomStarts() { return this.decoder.gomStarts(); }

  // Seeks to the GOM start at or before frame `index` (stream frame index); resolves with that
  // start's index once it has arrived and the next() frame is that start. `buffering(true)` is
  // called while waiting for bytes.
  seek(index, buffering) {
    this.interrupt();
    return this.schedule(async () => {
      const first = this.info.firstFrame;
      const known = () => this.finished || this.gomStarts().some((s) => s - first > index);
      if (!known()) {
        buffering(true);
        await this.until(known);
        buffering(false);
      }
      let start = first;
      for (const s of this.gomStarts()) if (s - first <= index) start = s;
      this.pending = undefined;
      if (this.videos) for (const v of this.videos) v.reset();
      this.decoder.seek(start);
      return start - first;
    });
  }

  // 3dvo-dec's MD5 lines for the frames hashed so far, in its order: per GOM the geometry lines,
  // then per frame per camera the texture lines; the header line once every frame is in.
  md5Lines() {
    if (!this.md5 || !this.info) return [];
    const { geometry, texture, gomStart } = this.md5;
    const lines = [], cameras = this.info.cameras.length;
    let gomTextures = [], complete = true;
    for (let i = 0; i < this.info.frameCount; ++i) {
      if (!geometry[i] || (cameras && !texture[i] && this.videos)) { complete = false; break; }
      if (cameras && gomStart[i]) lines.push(...gomTextures.splice(0));
      lines.push(geometry[i]);
      if (texture[i]) gomTextures.push(...texture[i]);
    }
    lines.push(...gomTextures);
    if (complete) lines.push(this.decoder.headerHashLine());
    return lines;
  }

  close() {
    if (this.videos) for (const v of this.videos) v.close();
    this.decoder.delete();
  }
}
