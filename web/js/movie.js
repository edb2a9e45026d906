// Reads movie.bin, the particles of a run at every movie_d_eps of imposed strain
// (schema/movie-format.md): a 96-byte little-endian header, then frames of the same size, each
// the strain (float64), x and y quantised to uint16 over the header's box, and the plastic
// strain rate as a uint8 level of log10(1 + rate) over [0, rate_log10_max].

const MAGIC = 'CSMOVIE1';
const HEADER_BYTES = 96;
export const PERIODIC_X = 1;

const littleEndian = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

// The header and a view of each frame (no copy on little-endian hosts, every browser's).
export function parseMovie(buffer) {
  const bytes = new Uint8Array(buffer);
  if (bytes.length < HEADER_BYTES || new TextDecoder('latin1').decode(bytes.subarray(0, 8)) !== MAGIC) throw new Error('not a movie.bin (magic CSMOVIE1)');
  const v = new DataView(buffer);
  if (v.getUint32(8, true) !== 1) throw new Error(`movie.bin version ${v.getUint32(8, true)} is not supported`);
  if (v.getUint32(12, true) !== HEADER_BYTES) throw new Error('movie.bin: unexpected header size');
  const n = Number(v.getBigUint64(16, true));
  const count = Number(v.getBigUint64(24, true));
  const frameBytes = Number(v.getBigUint64(32, true));
  if (frameBytes !== Math.ceil((8 + 5 * n) / 8) * 8) throw new Error('movie.bin: frame size does not match the particle count');
  if (HEADER_BYTES + count * frameBytes > bytes.length) throw new Error('movie.bin: shorter than its frame count');
  const header = {
    n, count, frameBytes,
    dEps: v.getFloat64(40, true),
    xLo: v.getFloat64(48, true), xHi: v.getFloat64(56, true), yLo: v.getFloat64(64, true), yHi: v.getFloat64(72, true),
    rateLog10Max: v.getFloat64(80, true),
    flags: v.getUint32(88, true),
  };
  const u16 = (offset) => {
    if (littleEndian) return new Uint16Array(buffer, offset, n);
    const out = new Uint16Array(n);
    for (let i = 0; i < n; i++) out[i] = v.getUint16(offset + 2 * i, true);
    return out;
  };
  const frames = [];
  for (let k = 0; k < count; k++) {
    const o = HEADER_BYTES + k * frameBytes;
    frames.push({ eps: v.getFloat64(o, true), x: u16(o + 8), y: u16(o + 8 + 2 * n), level: new Uint8Array(buffer, o + 8 + 4 * n, n) });
  }
  return { header, frames };
}
