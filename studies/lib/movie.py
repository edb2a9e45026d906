"""A bundle's movie.bin (schema/movie-format.md): its header, and the particles of each frame
(positions in metres, plastic strain rate / (V / h0)). Standard library only."""
import array
import os
import struct
import sys

MAGIC = b"CSMOVIE1"
HEADER_BYTES = 96


class Movie:
    """movie.bin of the bundle `out`, read whole (a 70 000-particle run to eps = 0.6 is 10 MB)."""

    def __init__(self, out):
        with open(os.path.join(out, "movie.bin"), "rb") as f:
            self.raw = f.read()
        if len(self.raw) < HEADER_BYTES or self.raw[:8] != MAGIC:
            raise ValueError("%s/movie.bin: not a movie (magic %r)" % (out, self.raw[:8]))
        version, header = struct.unpack_from("<II", self.raw, 8)
        if version != 1 or header != HEADER_BYTES:
            raise ValueError("%s/movie.bin: format %d with a %d-byte header, this reader knows "
                             "format 1 (96 bytes)" % (out, version, header))
        self.n, self.n_frames, self.frame_bytes = struct.unpack_from("<QQQ", self.raw, 16)
        (self.d_eps, self.x_lo, self.x_hi, self.y_lo, self.y_hi,
         self.rate_log10_max) = struct.unpack_from("<6d", self.raw, 40)
        self.periodic_x = bool(struct.unpack_from("<I", self.raw, 88)[0] & 1)
        if len(self.raw) < HEADER_BYTES + self.n_frames * self.frame_bytes:
            raise ValueError("%s/movie.bin: %d frames announced, the file holds fewer"
                             % (out, self.n_frames))

    def _uint16(self, offset):
        a = array.array("H")
        a.frombytes(self.raw[offset:offset + 2 * self.n])
        if sys.byteorder != "little":
            a.byteswap()
        return a

    def _offset(self, k):
        if not 0 <= k < self.n_frames:
            raise IndexError("frame %d of %d" % (k, self.n_frames))
        return HEADER_BYTES + k * self.frame_bytes

    def heights(self, k):
        """(eps, y) of frame k: the imposed strain and the particles' heights."""
        off = self._offset(k)
        sy = (self.y_hi - self.y_lo) / 65535
        return (struct.unpack_from("<d", self.raw, off)[0],
                [self.y_lo + q * sy for q in self._uint16(off + 8 + 2 * self.n)])

    def frame(self, k):
        """(eps, x, y, rate) of frame k: the imposed strain and the particles' lists."""
        off, n = self._offset(k), self.n
        eps, y = self.heights(k)
        sx = (self.x_hi - self.x_lo) / 65535
        x = [self.x_lo + q * sx for q in self._uint16(off + 8)]
        step = self.rate_log10_max / 255
        rate = [10.0 ** (v * step) - 1 for v in self.raw[off + 8 + 4 * n:off + 8 + 5 * n]]
        return eps, x, y, rate
