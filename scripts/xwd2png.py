#!/usr/bin/env python3
"""Converts an X window dump (XWD, ZPixmap, 24/32 bits per pixel, as Xvfb's
-fbdir screen file is) to an 8-bit RGB PNG, cropped to X,Y,W,H when given.
Standard library only. usage: xwd2png.py IN.xwd OUT.png [X,Y,W,H]"""
import struct
import sys
import zlib


def read_xwd(path):
    data = open(path, "rb").read()
    hdr = struct.unpack(">25I", data[:100])
    size, version, fmt, depth, width, height = hdr[:6]
    byte_order, bpp, bpl, ncolors = hdr[7], hdr[11], hdr[12], hdr[19]
    masks = hdr[14:17]
    if version != 7 or fmt != 2 or bpp not in (24, 32):
        sys.exit(f"xwd2png: {path}: not a 24/32-bit ZPixmap XWD (version {version}, format {fmt}, {bpp} bpp)")
    off = size + 12 * ncolors
    shifts = [(m & -m).bit_length() - 1 for m in masks]
    step = bpp // 8
    rows = []
    for y in range(height):
        line = data[off + y * bpl: off + y * bpl + width * step]
        row = bytearray(3 * width)
        for x in range(width):
            px = int.from_bytes(line[x * step:(x + 1) * step], "little" if byte_order == 0 else "big")
            for c in range(3):
                row[3 * x + c] = (px & masks[c]) >> shifts[c]
        rows.append(bytes(row))
    return width, height, rows


def write_png(path, width, height, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\0" + r for r in rows)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    w, h, rows = read_xwd(sys.argv[1])
    if len(sys.argv) == 4:
        x, y, cw, ch = (int(v) for v in sys.argv[3].split(","))
        rows = [r[3 * x:3 * (x + cw)] for r in rows[y:y + ch]]
        w, h = cw, ch
    write_png(sys.argv[2], w, h, rows)


if __name__ == "__main__":
    main()
