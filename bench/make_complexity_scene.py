#!/usr/bin/env python3
"""Writes the complexity series of the paper's Fig. 8 (VLF §7.1, "Numbers of Polygons"):
one emitter, 224 to 1736 polygons, diffuse : specular faces = 5 : 1.

Each scene is a closed 6 m room (6 faces, seen from inside), a square ceiling lamp hung
5 mm below the ceiling (1 face), a wall mirror 5 mm in front of the back wall (1 face) and
k floating cubes (6 faces each) spread evenly over an n x n x n lattice, n = ceil(k^(1/3));
every sixth cube is a mirror. faces = 8 + 6k, so the default sizes 224, 530, 836, 1124,
1430, 1736 are k = 36, 87, 138, 186, 237, 288 cubes. Specular faces = 1 + 6*floor(k/6),
i.e. one in six of all faces (37 of 224 ... 289 of 1736).

Each cube (edge half the lattice pitch) is turned about y by a deterministic angle, so no two
faces are coplanar; neighbouring cubes are at least 0.29 pitches apart and every cube is
more than 0.3 m from the walls. Python 3 standard library only.

Usage: bench/make_complexity_scene.py [--out-dir scenes/complexity] [FACES ...]
"""
import argparse
import json
import math
import os
import sys

ROOM = 6.0          # room edge, m
GAP = 0.005         # lamp and mirror offsets from the surface behind them, m
DEFAULT_SIZES = [224, 530, 836, 1124, 1430, 1736]


def quad(axis, c, lo, hi, normal):
    """Rectangle in the plane x[axis] = c over lo..hi in the other two axes, counter-clockwise
    seen from the side `normal` points to."""
    o = [i for i in range(3) if i != axis]
    pts = []
    for a, b in [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]:
        p = [0.0, 0.0, 0.0]
        p[axis], p[o[0]], p[o[1]] = c, a, b
        pts.append(p)
    e1 = [pts[1][i] - pts[0][i] for i in range(3)]
    e2 = [pts[2][i] - pts[0][i] for i in range(3)]
    n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    if sum(n[i] * normal[i] for i in range(3)) < 0:
        pts.reverse()
    return [[round(x, 4) for x in p] for p in pts]


def scene(faces):
    if faces < 8 + 6 or (faces - 8) % 6:
        raise ValueError(f"{faces} faces: need 8 + 6k with k >= 1 (e.g. 224, 530, 836, 1124, 1430, 1736)")
    k = (faces - 8) // 6
    n = math.ceil(round(k ** (1.0 / 3.0), 9))
    while n ** 3 < k:
        n += 1
    cells = n ** 3
    pitch = (ROOM - 0.6) / n          # lattice inside [0.3, ROOM - 0.3]^3
    size = 0.5 * pitch                # cube edge; rotated cubes stay within 0.71 * pitch
    objs = [
        {"name": "floor", "type": "polygon", "material": "white",
         "vertices": quad(1, 0.0, [0, 0], [ROOM, ROOM], [0, 1, 0])},
        {"name": "ceiling", "type": "polygon", "material": "white",
         "vertices": quad(1, ROOM, [0, 0], [ROOM, ROOM], [0, -1, 0])},
        {"name": "wall -x", "type": "polygon", "material": "red",
         "vertices": quad(0, 0.0, [0, 0], [ROOM, ROOM], [1, 0, 0])},
        {"name": "wall +x", "type": "polygon", "material": "green",
         "vertices": quad(0, ROOM, [0, 0], [ROOM, ROOM], [-1, 0, 0])},
        {"name": "wall -z", "type": "polygon", "material": "white",
         "vertices": quad(2, 0.0, [0, 0], [ROOM, ROOM], [0, 0, 1])},
        {"name": "wall +z", "type": "polygon", "material": "white",
         "vertices": quad(2, ROOM, [0, 0], [ROOM, ROOM], [0, 0, -1])},
        {"name": "lamp", "type": "polygon", "material": "lamp",
         "vertices": quad(1, ROOM - GAP, [2.25, 2.25], [3.75, 3.75], [0, -1, 0])},
        {"name": "wall mirror", "type": "polygon", "material": "mirror",
         "vertices": quad(2, ROOM - GAP, [1.0, 0.5], [5.0, 4.5], [0, 0, -1])},
    ]
    for i in range(k):
        c = (i * cells) // k          # spread the k cubes evenly over the lattice
        ix, iy, iz = c % n, (c // n) % n, c // (n * n)
        centre = [0.3 + (ix + 0.5) * pitch, 0.3 + (iy + 0.5) * pitch, 0.3 + (iz + 0.5) * pitch]
        h = size / 2
        objs.append({
            "name": f"cube {i}", "type": "box",
            "min": [round(x - h, 4) for x in centre], "max": [round(x + h, 4) for x in centre],
            "rotate_y_deg": round((37.0 * i) % 90.0 + 5.0, 1),
            "material": "mirror" if i % 6 == 5 else "grey",
        })
    specular = 1 + 6 * (k // 6)
    return {
        "settings": {"units": "m"},
        "materials": {
            "white": {"diffuse": [0.75, 0.75, 0.75]},
            "red": {"diffuse": [0.63, 0.065, 0.05]},
            "green": {"diffuse": [0.14, 0.45, 0.091]},
            "grey": {"diffuse": [0.55, 0.55, 0.55]},
            "mirror": {"specular": [0.9, 0.9, 0.9]},
            "lamp": {"diffuse": [0.78, 0.78, 0.78], "emission": [15.0, 15.0, 15.0]},
        },
        "objects": objs,
        "cameras": [{"name": "default", "eye": [3.0, 3.0, 0.05], "look_at": [3.0, 3.0, 6.0],
                     "up": [0.0, 1.0, 0.0], "fov_y_deg": 80.0}],
    }, k, specular


def dump(s):
    lines = ["{", f'  "settings": {json.dumps(s["settings"])},', '  "materials": {']
    mats = list(s["materials"].items())
    lines += [f"    {json.dumps(k)}: {json.dumps(v)}" + ("," if i < len(mats) - 1 else "")
              for i, (k, v) in enumerate(mats)]
    lines += ["  },", '  "objects": [']
    lines += ["    " + json.dumps(o) + ("," if i < len(s["objects"]) - 1 else "")
              for i, o in enumerate(s["objects"])]
    lines += ["  ],", '  "cameras": [']
    lines += ["    " + json.dumps(c) + ("," if i < len(s["cameras"]) - 1 else "")
              for i, c in enumerate(s["cameras"])]
    lines += ["  ]", "}"]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out-dir", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                      "..", "scenes", "complexity"))
    ap.add_argument("faces", nargs="*", type=int, default=DEFAULT_SIZES)
    args = ap.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    for faces in args.faces:
        try:
            s, k, spec = scene(faces)
        except ValueError as e:
            print(f"make_complexity_scene.py: {e}", file=sys.stderr)
            return 2
        path = os.path.join(args.out_dir, f"complexity-{faces}.json")
        with open(path, "w") as f:
            f.write(dump(s))
        print(f"{os.path.normpath(path)}: {faces} faces ({k} cubes), 1 emitter, "
              f"{spec} specular, diffuse:specular = {(faces - spec) / spec:.2f}:1", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
