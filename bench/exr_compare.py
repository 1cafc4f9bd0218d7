#!/usr/bin/env python3
"""Averages path-traced EXRs and maps where two images differ (glass references, issue 14).
Python 3 standard library only; reads what bench/exr_to_png.py reads (walkthrough's EXRs).

  bench/exr_compare.py mean OUT.exr A.exr[:W] B.exr[:W] ...
      the pixel-wise mean, each image weighted by W (its spp; default 1), written as an
      uncompressed float EXR: two references of different seeds make one of their summed spp.
  bench/exr_compare.py map IMAGE.exr REFERENCE.exr OUT.png [--scale S] [--block B]
      an error map: per pixel |image - reference| (RGB length) over the reference's mean
      pixel length, as grey (0 = black, S = white; default S = 0.5), and signed in colour:
      red where the image is brighter, blue where darker. --block B averages B x B pixels
      of both first (what remains is the error of the low frequencies, not the noise).
      Prints the relative RMSE of the whole image and of each quarter, and the error's share
      per horizontal band of the image (where the error is).
  bench/exr_compare.py ratios IMAGE.exr REFERENCE.exr [--block B]
      the table of image / reference per B x B block (default 16), the RGB sums of each
      block's pixels: where a bake and a reference differ, beyond the noise of either.
  bench/exr_compare.py shrink IMAGE.exr OUT.exr --block B
      the mean of each B x B block of pixels, written as an uncompressed float EXR: a
      512 x 512 path-traced image at S spp becomes a 128 x 128 one (B 4) at 16 S spp,
      stratified over each pixel's 16 sub-pixels (the same pixel footprint).
"""
import argparse
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exr_to_png import read_exr  # noqa: E402


def write_exr(path, width, height, rgb):
    def attr(name, kind, body):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(body)) + body

    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) +
              attr("channels", "chlist", chl) +
              attr("compression", "compression", b"\0") +
              attr("dataWindow", "box2i", struct.pack("<4i", 0, 0, width - 1, height - 1)) +
              attr("displayWindow", "box2i", struct.pack("<4i", 0, 0, width - 1, height - 1)) +
              attr("lineOrder", "lineOrder", b"\0") +
              attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attr("screenWindowCenter", "v2f", struct.pack("<2f", 0.0, 0.0)) +
              attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    row = 3 * 4 * width
    first = len(header) + 8 * height
    offsets = struct.pack(f"<{height}Q", *[first + y * (8 + row) for y in range(height)])
    body = bytearray()
    for y in range(height):
        body += struct.pack("<ii", y, row)
        for c in (2, 1, 0):  # B, G, R: alphabetical
            body += struct.pack(f"<{width}f", *rgb[c][y * width:(y + 1) * width])
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header + offsets + body)
    os.replace(tmp, path)


def mean(args):
    total, acc, size = 0.0, None, None
    for spec in args.inputs:
        name, _, w = spec.partition(":")
        w = float(w) if w else 1.0
        width, height, rgb = read_exr(name)
        if size and size != (width, height):
            sys.exit(f"{name}: {width}x{height}, not {size[0]}x{size[1]}")
        size = (width, height)
        if acc is None:
            acc = [[0.0] * (width * height) for _ in range(3)]
        for c in range(3):
            a, src = acc[c], rgb[c]
            for i in range(len(a)):
                a[i] += w * src[i]
        total += w
    write_exr(args.output, size[0], size[1], [[v / total for v in ch] for ch in acc])


def blocks(width, height, rgb, b):
    w, h = width // b, height // b
    out = [[0.0] * (w * h) for _ in range(3)]
    for c in range(3):
        for y in range(h * b):
            for x in range(w * b):
                out[c][(y // b) * w + x // b] += rgb[c][y * width + x] / (b * b)
    return w, h, out


def read_pair(image, reference, block):
    """Both images (of one size), each averaged over block x block pixels when block > 1."""
    wa, ha, a = read_exr(image)
    wb, hb, r = read_exr(reference)
    if (wa, ha) != (wb, hb):
        sys.exit(f"sizes differ: {wa}x{ha} and {wb}x{hb}")
    if block > 1:
        wa, ha, a = blocks(wa, ha, a, block)
        _, _, r = blocks(wb, hb, r, block)
    return wa, ha, a, r


def error_map(args):
    wa, ha, a, r = read_pair(args.image, args.reference, args.block)
    n = wa * ha
    d = [[a[c][i] - r[c][i] for i in range(n)] for c in range(3)]
    err = [math.sqrt(sum(d[c][i] ** 2 for c in range(3))) for i in range(n)]
    ref = [math.sqrt(sum(r[c][i] ** 2 for c in range(3))) for i in range(n)]
    scale = sum(ref) / n

    def rel(idx):
        num = sum(err[i] ** 2 for i in idx)
        den = sum(ref[i] ** 2 for i in idx)
        return math.sqrt(num / den) if den > 0 else 0.0

    print(f"relative RMSE, whole image: {rel(range(n)):.4f}")
    for name, (x0, y0) in {"top left": (0, 0), "top right": (1, 0), "bottom left": (0, 1),
                           "bottom right": (1, 1)}.items():
        idx = [y * wa + x for y in range(y0 * ha // 2, (y0 + 1) * ha // 2)
               for x in range(x0 * wa // 2, (x0 + 1) * wa // 2)]
        print(f"  {name}: {rel(idx):.4f}")
    total = sum(e * e for e in err) or 1.0
    bands = 8
    shares = []
    for k in range(bands):
        idx = range(k * ha // bands * wa, (k + 1) * ha // bands * wa)
        shares.append(sum(err[i] ** 2 for i in idx) / total)
    print("share of the squared error per eighth of the image, top to bottom: " +
          " ".join(f"{s:.2f}" for s in shares))
    pixels = bytearray()
    import zlib
    for y in range(ha):
        pixels.append(0)
        for x in range(wa):
            i = y * wa + x
            v = min(1.0, err[i] / (scale * args.scale))
            sign = sum(d[c][i] for c in range(3))
            g = int(255 * v + 0.5)
            pixels += bytes((g, int(g * 0.35), int(g * 0.35)) if sign > 0 else
                            (int(g * 0.35), int(g * 0.35), g))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body +
                struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    with open(args.output, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", wa, ha, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(bytes(pixels), 9)) + chunk(b"IEND", b""))


def ratios(args):
    w, h, a, r = read_pair(args.image, args.reference, args.block)
    for y in range(h):
        row = []
        for x in range(w):
            i = y * w + x
            num, den = sum(a[c][i] for c in range(3)), sum(r[c][i] for c in range(3))
            row.append(f"{num / den:5.3f}" if den > 0 else "  -  ")
        print(" ".join(row))


def shrink(args):
    w, h, rgb = read_exr(args.image)
    if w % args.block or h % args.block:
        sys.exit(f"{args.image}: {w}x{h} is not a multiple of {args.block}")
    write_exr(args.output, *blocks(w, h, rgb, args.block))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("mean")
    m.add_argument("output")
    m.add_argument("inputs", nargs="+")
    e = sub.add_parser("map")
    e.add_argument("image")
    e.add_argument("reference")
    e.add_argument("output")
    e.add_argument("--scale", type=float, default=0.5)
    e.add_argument("--block", type=int, default=1)
    q = sub.add_parser("ratios")
    q.add_argument("image")
    q.add_argument("reference")
    q.add_argument("--block", type=int, default=16)
    k = sub.add_parser("shrink")
    k.add_argument("image")
    k.add_argument("output")
    k.add_argument("--block", type=int, required=True)
    args = ap.parse_args()
    {"mean": mean, "map": error_map, "ratios": ratios, "shrink": shrink}[args.cmd](args)


if __name__ == "__main__":
    main()
