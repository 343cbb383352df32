"""Reads X Window Dump files (xwd -silent), the 24/32-bit ZPixmap that Xvfb
gives, into an H x W x 3 uint8 numpy array (RGB)."""
import struct

import numpy as np


def read(data):
    fields = struct.unpack(">25I", data[:100])
    (header_size, _version, fmt, _depth, width, height, _xoff, byte_order, _unit, _bit_order, _pad, bpp,
     bytes_per_line, _visual, red_mask, green_mask, blue_mask, _bits_rgb, _cmap, ncolors) = fields[:20]
    if fmt != 2 or bpp not in (24, 32):
        raise ValueError(f"unsupported XWD: format {fmt}, {bpp} bits per pixel")
    start = header_size + 12 * ncolors
    raw = np.frombuffer(data, dtype=np.uint8, count=bytes_per_line * height, offset=start)
    rows = raw.reshape(height, bytes_per_line)[:, : width * (bpp // 8)].reshape(height, width, bpp // 8)
    # Assemble each pixel as an integer in the file's byte order, then mask.
    weights = [1 << (8 * i) for i in range(bpp // 8)]
    if byte_order == 1:  # MSBFirst
        weights = weights[::-1]
    pix = sum(rows[:, :, i].astype(np.uint32) * w for i, w in enumerate(weights))
    out = np.zeros((height, width, 3), dtype=np.uint8)
    for ch, mask in enumerate((red_mask, green_mask, blue_mask)):
        shift = (mask & -mask).bit_length() - 1
        out[:, :, ch] = ((pix & mask) >> shift).astype(np.uint8)
    return out
