#!/usr/bin/env python3
"""The triangulated twin of scenes/floor-quad.json: the same room, whose floor quad is replaced
by a mesh of N random triangles (default 10,000) covering exactly the same rectangle.

How: an nx x nz grid of points over the floor rectangle, each point jittered at random by up
to 0.2 of a cell along each axis (points on the rectangle's sides move only along their side,
corners stay; inner coordinates are rounded to 1e-6 to keep the file small), which keeps every
cell a strictly convex quad; each cell is cut along a random
diagonal into 2 triangles, and r of the cells instead into 4 about their corners' mean, so that
2*nx*nz + 2*r = N exactly. The seed is fixed, so the output is the same on every run.

Checks, in exact rational arithmetic on the coordinates as written to the OBJ (Python writes the
shortest decimal that reads back as the same double, so the file *is* the checked geometry):
every triangle faces up (+y, the quad's normal) with area > 0; every inner edge is shared by
exactly two triangles in opposite directions and every other edge lies on the rectangle's
boundary — so the triangles cover the rectangle once, without overlaps or gaps; and the sum of
the areas equals the rectangle's area (also in floating point, to 1e-12 relative).

Writes SCENE_DIR/NAME.json (floor-quad.json with its "floor" object swapped for the mesh) and
SCENE_DIR/meshes/NAME.obj. Python 3 standard library only.
Usage: bench/make_triangulated_floor.py [--triangles N] [--seed S] [--base scenes/floor-quad.json]
                                        [--name floor-triangles] [--scene-dir scenes]
"""
import argparse
import json
import math
import os
import random
import re
import sys
from fractions import Fraction


def floor_rectangle(scene):
    """x0, x1, z0, z1, y of the axis-aligned rectangle of the object named "floor"."""
    floor = next(o for o in scene["objects"] if o.get("name") == "floor")
    assert floor["type"] == "polygon", "the floor must be a polygon"
    vs = floor["vertices"]
    ys = {v[1] for v in vs}
    xs, zs = sorted({v[0] for v in vs}), sorted({v[2] for v in vs})
    assert len(vs) == 4 and len(ys) == 1 and len(xs) == 2 and len(zs) == 2, \
        "the floor must be an axis-aligned rectangle in a plane y = const"
    return xs[0], xs[1], zs[0], zs[1], ys.pop(), floor


def triangulate(n_tri, x0, x1, z0, z1, rng):
    """Points (x, z) and triangles (index triples, counter-clockwise seen from +y)."""
    assert n_tri >= 2 and n_tri % 2 == 0, "the triangle count must be even and >= 2"
    half = n_tri // 2
    nx = max(1, round(math.sqrt(half * (x1 - x0) / (z1 - z0))))  # cells along x
    nz = max(1, half // nx)
    r = half - nx * nz  # cells cut into 4 instead of 2
    assert 0 <= r <= nx * nz, "too few cells for the requested count"
    hx, hz = (x1 - x0) / nx, (z1 - z0) / nz
    jitter = 0.2

    def coord(i, n, lo, hi, h):
        if i == 0:
            return lo
        if i == n:
            return hi
        return round(lo + (i + rng.uniform(-jitter, jitter)) * h, 6)  # short in the file

    points, index = [], {}
    for i in range(nx + 1):
        for k in range(nz + 1):
            index[i, k] = len(points)
            # a side point moves only along its side: its other coordinate is exactly lo or hi
            points.append((coord(i, nx, x0, x1, hx), coord(k, nz, z0, z1, hz)))
    four = set(rng.sample(range(nx * nz), r))
    tris = []
    for i in range(nx):
        for k in range(nz):
            # Corners counter-clockwise seen from +y: with x right and z down the page, +y
            # points into it, so the order is (x0,z0) -> (x0,z1) -> (x1,z1) -> (x1,z0).
            a, b, c, d = index[i, k], index[i, k + 1], index[i + 1, k + 1], index[i + 1, k]
            if i * nz + k in four:
                e = len(points)
                mean = [sum(points[p][j] for p in (a, b, c, d)) / 4 for j in (0, 1)]
                points.append((round(mean[0], 6), round(mean[1], 6)))
                tris += [(a, b, e), (b, c, e), (c, d, e), (d, a, e)]
            elif rng.random() < 0.5:
                tris += [(a, b, c), (a, c, d)]
            else:
                tris += [(a, b, d), (b, c, d)]
    return points, tris


def write_obj(path, points, tris, y, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n# {len(points)} vertices, {len(tris)} triangles\n")
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, z in points)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)


def check_obj(path, x0, x1, z0, z1, y):
    """Exact coverage check of the written file; returns the float relative area error."""
    pts, tris = [], []
    for line in open(path):
        if line.startswith("v "):
            px, py, pz = (Fraction(t) for t in line.split()[1:4])  # exact decimal values
            assert py == Fraction(y), "a vertex off the floor plane"
            assert Fraction(x0) <= px <= Fraction(x1) and Fraction(z0) <= pz <= Fraction(z1), \
                "a vertex outside the rectangle"
            pts.append((px, pz))
        elif line.startswith("f "):
            tris.append(tuple(int(t) - 1 for t in line.split()[1:4]))
    total, float_areas, edges = Fraction(0), [], {}
    for a, b, c in tris:
        (ax, az), (bx, bz), (cx, cz) = pts[a], pts[b], pts[c]
        ny = (bz - az) * (cx - ax) - (bx - ax) * (cz - az)  # y of (b-a) x (c-a)
        assert ny > 0, f"triangle {a + 1} {b + 1} {c + 1} is degenerate or faces down"
        total += ny / 2
        float_areas.append(float(ny) / 2)
        for p, q in ((a, b), (b, c), (c, a)):
            assert (p, q) not in edges, f"edge {p + 1}-{q + 1} used twice in one direction"
            edges[p, q] = True
    X0, X1, Z0, Z1 = (Fraction(v) for v in (x0, x1, z0, z1))
    for p, q in edges:
        if (q, p) in edges:
            continue  # inner edge, shared in opposite directions
        (px, pz), (qx, qz) = pts[p], pts[q]
        assert (px == qx and px in (X0, X1)) or (pz == qz and pz in (Z0, Z1)), \
            f"open edge {p + 1}-{q + 1} inside the rectangle (a gap)"
    quad = (X1 - X0) * (Z1 - Z0)
    assert total == quad, f"areas sum to {float(total)!r}, the rectangle has {float(quad)!r}"
    rel = abs(math.fsum(float_areas) - float(quad)) / float(quad)
    assert rel <= 1e-12, f"floating-point area sum off by {rel:.3g} relative"
    return rel


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--triangles", type=int, default=10000, help="triangle count (even)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--base", default="scenes/floor-quad.json", help="scene with a 'floor' quad")
    ap.add_argument("--name", default="floor-triangles", help="output scene/mesh name")
    ap.add_argument("--scene-dir", default="scenes", help="where NAME.json and meshes/ go")
    args = ap.parse_args()

    scene = json.load(open(args.base))
    x0, x1, z0, z1, y, floor = floor_rectangle(scene)
    points, tris = triangulate(args.triangles, x0, x1, z0, z1, random.Random(args.seed))
    os.makedirs(os.path.join(args.scene_dir, "meshes"), exist_ok=True)
    obj = os.path.join(args.scene_dir, "meshes", args.name + ".obj")
    write_obj(obj, points, tris, y, f"floor of {args.base} as {len(tris)} random triangles: "
              f"bench/make_triangulated_floor.py --triangles {args.triangles} --seed {args.seed}")
    rel = check_obj(obj, x0, x1, z0, z1, y)

    # The twin scene: the base file's text with the floor object replaced, so everything else
    # (materials, walls, lamp, cameras, layout) stays byte-identical.
    text = open(args.base).read()
    mesh = (f'{{"name": "floor", "type": "mesh", "material": "{floor["material"]}",\n'
            f'     "file": "meshes/{args.name}.obj"}}')
    text, n = re.subn(r'\{"name": "floor", "type": "polygon".*?\]\]\}', mesh, text, flags=re.S)
    assert n == 1, "could not find the floor object's text in the base scene"
    assert [o.get("file") for o in json.loads(text)["objects"] if o.get("name") == "floor"] == \
        [f"meshes/{args.name}.obj"]
    out = os.path.join(args.scene_dir, args.name + ".json")
    with open(out, "w") as f:
        f.write(text)
    print(f"{out}, {obj}: {len(tris)} triangles, {len(points)} vertices; exact cover of "
          f"[{x0}, {x1}] x [{z0}, {z1}] checked (float area error {rel:.1e} relative)",
          file=sys.stderr)


if __name__ == "__main__":
    main()
