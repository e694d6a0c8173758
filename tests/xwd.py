"""Read an X Window Dump (``xwd -root``, 24/32-bit TrueColor ZPixmap) into an RGB array."""
import struct

import numpy as np


def read_xwd(path):
    """(H, W, 3) uint8, top row first, of a TrueColor xwd file with 24 or 32 bits per pixel."""
    with open(path, "rb") as handle:
        data = handle.read()
    header = struct.unpack(">25I", data[:100])
    header_size, version, pixmap_format, depth, width, height = header[:6]
    byte_order, bits_per_pixel, bytes_per_line = header[7], header[11], header[12]
    red_mask, green_mask, blue_mask = header[14], header[15], header[16]
    ncolors = header[19]
    if version != 7 or pixmap_format != 2 or bits_per_pixel not in (24, 32):
        raise ValueError(f"{path}: only 24/32-bit ZPixmap xwd files are read (got format {pixmap_format}, "
                         f"{bits_per_pixel} bits per pixel)")
    start = header_size + 12 * ncolors
    step = bits_per_pixel // 8
    rows = np.frombuffer(data[start:start + bytes_per_line * height], dtype=np.uint8)
    rows = rows.reshape(height, bytes_per_line)[:, :step * width].reshape(height, width, step)
    weights = 256 ** (np.arange(step)[::-1] if byte_order else np.arange(step))
    words = (rows.astype(np.uint64) * weights).sum(axis=-1).astype(np.uint32)
    out = np.empty((height, width, 3), dtype=np.uint8)
    for channel, mask in enumerate((red_mask, green_mask, blue_mask)):
        shift = (mask & -mask).bit_length() - 1
        out[..., channel] = (words & mask) >> shift
    return out
