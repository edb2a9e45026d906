// Reads NumPy .npy files (format 1.0/2.0, little-endian float32/float64/int32, C order), the
// format of spacetime.npy and snapshot_<eps>.npy (schema/bundle-format.md).

const DTYPES = { '<f4': Float32Array, '<f8': Float64Array, '<i4': Int32Array, '|u1': Uint8Array };

export function parseNpy(buffer) {
  const bytes = new Uint8Array(buffer);
  const magic = [0x93, 0x4e, 0x55, 0x4d, 0x50, 0x59]; // \x93NUMPY
  if (bytes.length < 10 || magic.some((b, i) => bytes[i] !== b)) throw new Error('not a .npy file');
  const major = bytes[6];
  const view = new DataView(buffer);
  const headerLen = major === 1 ? view.getUint16(8, true) : view.getUint32(8, true);
  const offset = (major === 1 ? 10 : 12) + headerLen;
  const header = new TextDecoder('latin1').decode(bytes.subarray(major === 1 ? 10 : 12, offset));
  const descr = /'descr':\s*'([^']+)'/.exec(header)?.[1];
  const fortran = /'fortran_order':\s*True/.test(header);
  const shapeText = /'shape':\s*\(([^)]*)\)/.exec(header)?.[1] ?? '';
  const shape = shapeText.split(',').map((s) => s.trim()).filter(Boolean).map(Number);
  const Type = DTYPES[descr];
  if (!Type) throw new Error(`unsupported dtype ${descr}`);
  if (fortran) throw new Error('fortran order is not supported');
  const count = shape.reduce((a, b) => a * b, 1);
  // Copy: the data offset need not be aligned to the element size.
  const data = new Type(buffer.slice(offset, offset + count * Type.BYTES_PER_ELEMENT));
  if (data.length !== count) throw new Error('truncated .npy file');
  return { shape, dtype: descr, data };
}
