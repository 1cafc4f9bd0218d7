#!/usr/bin/env python3
"""A closed torus as an OBJ of planar quads with vertex normals, for glass scenes
(scenes/caustics/glass-point.json: Iwasaki et al.'s glass torus, their Fig. 8 (b)).

The torus turns about the y axis through the origin: a circle of radius r (the tube) whose
centre runs on a circle of radius R in the plane y = 0. Vertex (i, j), i < U around the axis,
j < V around the tube, sits at angle u = 2 pi i / U about the axis and v = 2 pi j / V about the
tube:  ((R + r cos v) cos u, r sin v, -(R + r cos v) sin u), its normal (cos v cos u, sin v,
-cos v sin u) (the surface's own, which the scene loader interpolates across each face:
docs/scenes.md "Smooth shading"). Quad (i, j) joins the vertices (i, j), (i+1, j), (i+1, j+1),
(i, j+1), counter-clockwise seen from outside.

Each quad is planar: its two edges along the parallels v_j and v_(j+1) are chords of circles
about the y axis over the same angle, both perpendicular to the plane at the mid-angle that
bisects them, so they are parallel and the quad is an isosceles trapezoid. The script checks,
on the coordinates as written (12 significant digits): every quad's corners lie within 1e-9 R
of its plane, its normal points outward (the same side as its corners' normals), and every
directed edge is matched by exactly one reversed edge (closed, turned outward, as a dielectric
object must be). Python 3 standard library only; the output is the same on every run.
Usage: bench/make_torus.py [-R 1] [-r 0.4] [-U 40] [-V 16] [-o scenes/meshes/torus.obj]
"""
import argparse
import math
import sys
from collections import Counter


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-R", type=float, default=1.0, help="radius of the tube's centre circle")
    ap.add_argument("-r", type=float, default=0.4, help="radius of the tube")
    ap.add_argument("-U", type=int, default=40, help="quads around the axis")
    ap.add_argument("-V", type=int, default=16, help="quads around the tube")
    ap.add_argument("-o", default="scenes/meshes/torus.obj")
    a = ap.parse_args()
    if not (0 < a.r < a.R) or a.U < 3 or a.V < 3:
        sys.exit("need 0 < r < R, U >= 3, V >= 3")

    def vid(i, j):
        return (i % a.U) * a.V + (j % a.V)

    pos, nrm = [], []
    for i in range(a.U):
        u = 2 * math.pi * i / a.U
        for j in range(a.V):
            v = 2 * math.pi * j / a.V
            w = a.R + a.r * math.cos(v)
            pos.append((w * math.cos(u), a.r * math.sin(v), -w * math.sin(u)))
            nrm.append((math.cos(v) * math.cos(u), math.sin(v), -math.cos(v) * math.sin(u)))
    quads = [(vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1))
             for i in range(a.U) for j in range(a.V)]

    lines = [f"# torus R {a.R} r {a.r}: {a.U} x {a.V} quads, made by bench/make_torus.py"]
    lines += ["v " + " ".join(f"{x + 0.0:.12g}" for x in p) for p in pos]
    lines += ["vn " + " ".join(f"{x + 0.0:.12g}" for x in n) for n in nrm]
    lines += ["f " + " ".join(f"{k + 1}//{k + 1}" for k in q) for q in quads]
    text = "\n".join(lines) + "\n"

    # Check the geometry as written.
    back = [tuple(float(t) for t in l.split()[1:]) for l in text.splitlines() if l.startswith("v ")]

    def sub(p, q):
        return (p[0] - q[0], p[1] - q[1], p[2] - q[2])

    def cross(p, q):
        return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])

    def dot(p, q):
        return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]

    worst = 0.0
    for q in quads:
        c = [back[k] for k in q]
        n = cross(sub(c[2], c[0]), sub(c[3], c[1]))
        ln = math.sqrt(dot(n, n))
        n = (n[0] / ln, n[1] / ln, n[2] / ln)
        d = dot(n, c[0])
        worst = max(worst, max(abs(dot(n, p) - d) for p in c))
        if min(dot(n, nrm[k]) for k in q) <= 0.0:
            sys.exit(f"quad {q}: its normal points inward")
    if worst > 1e-9 * a.R:
        sys.exit(f"a quad is {worst:g} off its plane")
    edges = Counter((q[k], q[(k + 1) % 4]) for q in quads for k in range(4))
    if any(c != 1 or edges[(b, e)] != 1 for (e, b), c in edges.items()):
        sys.exit("the torus is not closed")
    with open(a.o, "w") as f:
        f.write(text)
    print(f"{a.o}: {len(pos)} vertices, {len(quads)} quads, worst plane deviation {worst:.2g}")


if __name__ == "__main__":
    main()
