// The cameras' textures with the browser's H.264 decoder (WebCodecs VideoDecoder), one decoder
// per camera, fed with the stream's texture access units (docs/bitstream.md section 6: Annex B,
// one picture per access unit, no reordering, an IDR with SPS and PPS at every GOM start).
// Decoded pictures come back as tightly packed I420 planes of the texture box (Y, then U, V;
// rows top to bottom), the layout the texture MD5 lines hash.

// The NAL unit types of an Annex B access unit, with the position of each unit's header byte.
function nalUnits(bytes) {
  const out = [];
  for (let i = 0; i + 3 < bytes.length; ++i) {
    if (bytes[i] === 0 && bytes[i + 1] === 0 && bytes[i + 2] === 1) {
      out.push({ type: bytes[i + 3] & 0x1f, at: i + 3 });
      i += 2;
    }
  }
  return out;
}

// True when the access unit holds an IDR picture (a GOM start).
export function isIdr(accessUnit) {
  return nalUnits(accessUnit).some((n) => n.type === 5);
}

// 'avc1.PPCCLL' (RFC 6381) from the access unit's SPS: profile_idc, the constraint flags and
// level_idc, the three bytes after the SPS's NAL header; null without an SPS.
export function codecString(accessUnit) {
  const sps = nalUnits(accessUnit).find((n) => n.type === 7);
  if (!sps || sps.at + 3 >= accessUnit.length) return null;
  const hex = (b) => b.toString(16).padStart(2, '0');
  return 'avc1.' + hex(accessUnit[sps.at + 1]) + hex(accessUnit[sps.at + 2]) + hex(accessUnit[sps.at + 3]);
}

// '' when this browser decodes `codec` with WebCodecs, else the one line the page shows.
export async function webCodecsProblem(codec) {
  if (typeof VideoDecoder === 'undefined')
    return 'this browser has no WebCodecs VideoDecoder (Chromium 94+, Safari 16.4+, Firefox 130+ ' +
           'have one; it needs a secure context: https or localhost): playing without textures';
  try {
    const { supported } = await VideoDecoder.isConfigSupported({ codec });
    if (supported) return '';
  } catch (e) {
    // an invalid codec string is "not supported" too
  }
  return `this browser's WebCodecs does not decode H.264 (${codec}): playing without textures`;
}

// One camera's decoder. decode() returns a promise of the picture's planes (null when a reset
// drops it); pictures come out in decode order, one per access unit.
export class CameraVideo {
  constructor(codec, box, onError) {
    this.codec = codec;
    this.box = box;
    this.onError = onError;
    this.pending = [];  // resolvers, oldest first
    this.decoder = new VideoDecoder({
      output: (frame) => this.output(frame),
      error: (e) => this.onError(new Error(`H.264 decoder: ${e.message}`)),
    });
    this.configure();
  }

  configure() {
    this.decoder.configure({ codec: this.codec, codedWidth: this.box.width,
                             codedHeight: this.box.height, optimizeForLatency: true });
  }

  decode(accessUnit, key, timestamp) {
    return new Promise((resolve) => {
      this.pending.push(resolve);
      this.decoder.decode(new EncodedVideoChunk({ type: key ? 'key' : 'delta', timestamp,
                                                  data: accessUnit }));
    });
  }

  async output(frame) {
    const resolve = this.pending.shift();
    try {
      const planes = await copyPlanes(frame, this.box.width, this.box.height);
      if (resolve) resolve(planes);
    } catch (e) {
      this.onError(e);
    } finally {
      frame.close();
    }
  }

  // Outputs every picture the decoder still holds (at the end of the stream); the next access
  // unit must then be an IDR.
  async flush() {
    if (this.decoder.state === 'configured') await this.decoder.flush();
  }

  // Drops every picture not yet out (their promises give null); the next access unit must be
  // an IDR (a GOM start).
  reset() {
    for (const resolve of this.pending.splice(0)) resolve(null);
    if (this.decoder.state !== 'closed') {
      this.decoder.reset();
      this.configure();
    }
  }

  close() {
    for (const resolve of this.pending.splice(0)) resolve(null);
    if (this.decoder.state !== 'closed') this.decoder.close();
  }
}

// The top-left width × height of a VideoFrame as I420 planes without padding.
async function copyPlanes(frame, width, height) {
  const lumaSize = width * height, chromaSize = lumaSize / 4;
  const out = new Uint8Array(lumaSize + 2 * chromaSize);
  const rect = { x: frame.visibleRect.x, y: frame.visibleRect.y, width, height };
  if (frame.format === 'I420') {
    await frame.copyTo(out, { rect, layout: [{ offset: 0, stride: width },
                                             { offset: lumaSize, stride: width / 2 },
                                             { offset: lumaSize + chromaSize, stride: width / 2 }] });
  } else if (frame.format === 'NV12') {  // hardware decoders: interleaved chroma
    const nv12 = new Uint8Array(lumaSize + 2 * chromaSize);
    await frame.copyTo(nv12, { rect, layout: [{ offset: 0, stride: width },
                                              { offset: lumaSize, stride: width }] });
    out.set(nv12.subarray(0, lumaSize));
    for (let i = 0; i < chromaSize; ++i) {
      out[lumaSize + i] = nv12[lumaSize + 2 * i];
      out[lumaSize + chromaSize + i] = nv12[lumaSize + 2 * i + 1];
    }
  } else {
    throw new Error(`H.264 decoder: pictures in format ${frame.format}, not I420 or NV12`);
  }
  return out;
}
