// TEMPORARY: the page's interface to the WebAssembly decoder on a module built before the
// streaming interface (docs/wasm.md) landed. With a module that has Decoder.growing this file
// does nothing; delete it once every build has it.
//
// On an older module it emulates what the page uses: growing() decodes once finish() has been
// called (no progressive start), the texture access units, the camera list and the header line
// are read here from the container (docs/bitstream.md sections 1, 2, 6), and md5Hex is plain
// JavaScript. The real interface reads all of these in the C++ decoder.

// RFC 1321 MD5 of a Uint8Array, as 32 lowercase hex digits.
function md5Hex(bytes) {
  const s = [7, 12, 17, 22, 5, 9, 14, 20, 4, 11, 16, 23, 6, 10, 15, 21];
  const k = Array.from({ length: 64 }, (_, i) => Math.floor(Math.abs(Math.sin(i + 1)) * 2 ** 32) >>> 0);
  const n = ((bytes.length + 8) >>> 6) + 1;
  const words = new Uint32Array(n * 16);
  for (let i = 0; i < bytes.length; ++i) words[i >> 2] |= bytes[i] << ((i % 4) * 8);
  words[bytes.length >> 2] |= 0x80 << ((bytes.length % 4) * 8);
  words[n * 16 - 2] = (bytes.length * 8) >>> 0;
  words[n * 16 - 1] = Math.floor(bytes.length / 2 ** 29);
  let [a0, b0, c0, d0] = [0x67452301, 0xefcdab89, 0x98badcfe, 0x10325476];
  for (let block = 0; block < n; ++block) {
    let [a, b, c, d] = [a0, b0, c0, d0];
    for (let i = 0; i < 64; ++i) {
      let f, g;
      if (i < 16) f = (b & c) | (~b & d), g = i;
      else if (i < 32) f = (d & b) | (~d & c), g = (5 * i + 1) % 16;
      else if (i < 48) f = b ^ c ^ d, g = (3 * i + 5) % 16;
      else f = c ^ (b | ~d), g = (7 * i) % 16;
      const x = (a + f + k[i] + words[block * 16 + g]) >>> 0;
      const r = s[(i >> 4) * 4 + (i % 4)];
      [a, d, c] = [d, c, b];
      b = (b + ((x << r) | (x >>> (32 - r)))) >>> 0;
    }
    a0 = (a0 + a) >>> 0, b0 = (b0 + b) >>> 0, c0 = (c0 + c) >>> 0, d0 = (d0 + d) >>> 0;
  }
  let hex = '';
  for (const w of [a0, b0, c0, d0])
    for (let i = 0; i < 4; ++i) hex += ((w >>> (8 * i)) & 0xff).toString(16).padStart(2, '0');
  return hex;
}

// The units of a whole stream: [{type, payload}] (CRCs are the decoder's business).
function units(bytes) {
  const out = [];
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  for (let at = 4; at + 5 <= bytes.length;) {
    const size = view.getUint32(at + 1, true);
    out.push({ type: bytes[at], payload: bytes.subarray(at + 5, at + 5 + size) });
    at += 9 + size;
  }
  return out;
}

// The sequence header's cameras, description and up (docs/bitstream.md section 2).
function parseHeader(payload) {
  const v = new DataView(payload.buffer, payload.byteOffset, payload.byteLength);
  let at = 0;
  const u8 = () => v.getUint8(at++);
  const u16 = () => { at += 2; return v.getUint16(at - 2, true); };
  const f64 = () => { at += 8; return v.getFloat64(at - 8, true); };
  const text = () => {
    const n = u16();
    at += n;
    return new TextDecoder().decode(payload.subarray(at - n, at));
  };
  const version = u16();
  at += 4 + 4 + 8 + 1 + 32;
  if (version >= 3) u8();
  const cameras = [];
  for (let i = u16(); i > 0; --i) {
    const name = text();
    const width = u16(), height = u16();
    const [fx, fy, cx, cy] = [f64(), f64(), f64(), f64()];
    const distortion = [f64(), f64(), f64(), f64(), f64()];
    const R = Array.from({ length: 9 }, f64), t = [f64(), f64(), f64()];
    const box = { x: u16(), y: u16(), width: u16(), height: u16() };
    cameras.push({ name, width, height, fx, fy, cx, cy, distortion, R, t, box });
  }
  let description = '', up = null;
  if (cameras.length) {
    description = text();
    if (u8()) up = [f64(), f64(), f64()];
  }
  return { cameras, description, up };
}

class GrowingDecoder {
  constructor(tdvo, name) {
    this.tdvo = tdvo;
    this.name = name;
    this.chunks = [];
    this.finished = false;
    this.decoder = null;
    this.textures = false;
  }
  append(chunk) { this.chunks.push(new Uint8Array(chunk)); }
  finish() {
    const length = this.chunks.reduce((n, c) => n + c.length, 0);
    this.bytes = new Uint8Array(length);
    let at = 0;
    for (const c of this.chunks) this.bytes.set(c, at), at += c.length;
    this.chunks = [];
    this.finished = true;
  }
  headerReady() {
    if (!this.finished) return false;
    if (!this.decoder) {
      this.decoder = new this.tdvo.Decoder(this.bytes, this.name);
      const all = units(this.bytes);
      this.header = all[0].payload;
      this.extra = parseHeader(this.header);
      this.textureUnits = new Map();  // frame index -> [camera] access unit
      for (const u of all.filter((x) => x.type === 5)) {
        const d = new DataView(u.payload.buffer, u.payload.byteOffset, 6);
        const frame = d.getUint32(0, true), camera = d.getUint16(4, true);
        if (!this.textureUnits.has(frame)) this.textureUnits.set(frame, []);
        this.textureUnits.get(frame)[camera] = u.payload.subarray(6);
      }
    }
    return true;
  }
  canDecodeNext() { return this.headerReady(); }
  info() { return { ...this.decoder.info(), ...this.extra }; }
  setTextureUnits(on) { this.textures = on; }
  textureUnit(c) { return this.textureUnits.get(this.decoder.frameIndex())[c]; }
  headerHashLine() { return 'MD5 header=' + md5Hex(this.header); }
  gomStarts() { return this.decoder ? this.decoder.gomStarts() : []; }
  delete() { if (this.decoder) this.decoder.delete(); }
}
for (const method of ['next', 'frameNumber', 'frameIndex', 'vertexCount', 'triangleCount',
                      'positions', 'gridPositions', 'triangles', 'geometryHashLine', 'seek'])
  GrowingDecoder.prototype[method] = function (...args) { return this.decoder[method](...args); };

// The module with the streaming interface (itself when it has it).
export function withStreamingInterface(tdvo) {
  if (tdvo.Decoder.growing) return tdvo;
  tdvo.Decoder.growing = (name) => new GrowingDecoder(tdvo, name);
  tdvo.md5Hex = md5Hex;
  return tdvo;
}
