#!/usr/bin/env python3
"""Midpoint subdivision of a triangle mesh: every triangle becomes 4 (its corners and the
midpoints of its edges), `--levels L` times, so the face count grows by 4**L while the surface
stays exactly the same (the new vertices lie on the old flat faces). Used to make the same
model at 1k ... 1M triangles (bench/scale.sh). Python 3 standard library only.

Reads an OBJ (`v` and `f` lines; texture/normal indices and other lines are ignored; faces
with more than 3 corners are fanned into triangles first) and writes an OBJ of positions and
triangles. Shared edges share their midpoint, so a closed mesh stays closed.

Usage: bench/subdivide_mesh.py IN.obj OUT.obj [--levels L]
"""
import argparse
import sys


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                idx = []
                for token in parts[1:]:
                    i = int(token.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(vertices) + i)  # negative = relative
                for k in range(1, len(idx) - 1):  # fan (planar convex faces only)
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return vertices, faces


def subdivide(vertices, faces):
    vertices = list(vertices)
    midpoint = {}  # (lo, hi) vertex pair -> index of the edge's midpoint

    def mid(a, b):
        key = (a, b) if a < b else (b, a)
        i = midpoint.get(key)
        if i is None:
            pa, pb = vertices[a], vertices[b]
            i = len(vertices)
            vertices.append(tuple((x + y) * 0.5 for x, y in zip(pa, pb)))
            midpoint[key] = i
        return i

    out = []
    for a, b, c in faces:  # the four children keep the parent's winding
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return vertices, out


def write_obj(path, vertices, faces, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n# {len(vertices)} vertices, {len(faces)} triangles\n")
        f.writelines("v %.9g %.9g %.9g\n" % v for v in vertices)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--levels", type=int, default=1, help="subdivision steps (4**L faces)")
    args = ap.parse_args()
    if args.levels < 0:
        ap.error("--levels must be >= 0")
    vertices, faces = read_obj(args.input)
    n0 = len(faces)
    for _ in range(args.levels):
        vertices, faces = subdivide(vertices, faces)
    write_obj(args.output, vertices, faces,
              f"{args.input} subdivided {args.levels}x by bench/subdivide_mesh.py")
    print(f"{args.output}: {n0} -> {len(faces)} triangles, {len(vertices)} vertices",
          file=sys.stderr)


if __name__ == "__main__":
    main()
