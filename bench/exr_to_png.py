#!/usr/bin/env python3
"""Tone-maps an EXR written by walkthrough into a PNG exactly as walkthrough's own PNG output
does (vlf/render/image_io.cpp: x * 2^EV, Reinhard x / (1 + x), sRGB, 8 bits), so a long
path-traced reference needs rendering once, as EXR, and can still be looked at.
Python 3 standard library only. It reads the files walkthrough writes: scanline, half or
float RGB(A), NONE, ZIPS or ZIP compression; it does not read tiled, deep or PIZ files.
Usage: bench/exr_to_png.py IN.exr OUT.png [--exposure EV]
"""
import argparse
import math
import struct
import sys
import zlib

LINES = {0: 1, 2: 1, 3: 16}  # compression -> scanlines per chunk (NONE, ZIPS, ZIP)


def read_exr(path):
    data = open(path, "rb").read()
    # magic; tiled, deep or multipart (long attribute names, bit 0x04, are read as any)
    if data[:4] != b"\x76\x2f\x31\x01" or data[5] & 0x1A:
        sys.exit(f"{path}: not a single-part scanline EXR")
    pos, attrs = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        attrs[data[pos:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        pos = type_end + 5 + size
    pos += 1
    channels, c = [], attrs["channels"]  # name\0, pixel type int, 12 more bytes each
    while c[0] != 0:
        end = c.index(b"\0")
        channels.append((c[:end].decode(), struct.unpack_from("<i", c, end + 1)[0]))
        c = c[end + 17:]
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    compression = attrs["compression"][0]
    if compression not in LINES:
        sys.exit(f"{path}: compression {compression} is not supported (NONE, ZIPS, ZIP only)")
    nlines = LINES[compression]
    sizes = {1: 2, 2: 4}  # HALF, FLOAT bytes (UINT is not an image channel here)
    fmt = {1: "e", 2: "f"}
    row_bytes = sum(width * sizes[t] for _, t in channels)
    pixels = {name: [] for name, _ in channels}
    nchunks = (height + nlines - 1) // nlines
    offsets = struct.unpack_from(f"<{nchunks}Q", data, pos)
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        raw = data[off + 8:off + 8 + size]
        rows = min(nlines, y1 - y + 1)
        if size < rows * row_bytes:  # compressed (OpenEXR keeps a chunk raw if zip is larger)
            t = bytearray(zlib.decompress(raw))
            for i in range(1, len(t)):  # undo the predictor
                t[i] = (t[i - 1] + t[i] - 128) & 0xFF
            half = (len(t) + 1) // 2  # undo the byte interleave
            raw = bytearray(len(t))
            raw[0::2], raw[1::2] = t[:half], t[half:]
        p = 0
        for _ in range(rows):
            for name, ptype in channels:  # channels are stored in alphabetical order
                n = width * sizes[ptype]
                pixels[name].extend(struct.unpack_from(f"<{width}{fmt[ptype]}", raw, p))
                p += n
    return width, height, [pixels[c] for c in "RGB"]


def srgb(c):
    return 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055


def write_png(path, width, height, rgb, exposure):
    scale = 2.0 ** exposure

    def byte(x):
        x *= scale
        if not math.isfinite(x) or x < 0:
            x = 1e30 if x > 0 else 0.0
        return max(0, min(255, math.floor(srgb(x / (1 + x)) * 255 + 0.5)))  # std::lround

    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(y * width, (y + 1) * width):
            rows += bytes(byte(ch[x]) for ch in rgb)

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))  # 8-bit RGB
        f.write(chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b""))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--exposure", type=float, default=0.0, help="stops, as walkthrough --exposure")
    args = ap.parse_args()
    width, height, rgb = read_exr(args.input)
    write_png(args.output, width, height, rgb, args.exposure)


if __name__ == "__main__":
    main()
