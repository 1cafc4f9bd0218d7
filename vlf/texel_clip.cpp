#include "vlf/texel_clip.hpp"

#include <algorithm>
#include <cmath>

namespace vlf {

PsfToTexel psf_to_texel(const Face& face, const Mat3& rotation) {
    // Rotated-frame point on the plane: q = (x, y, z(x, y)), z = (D - n.x x - n.y y) / n.z,
    // scene point p = R^T q, texel = ((p - o).au, (p - o).av) / size. All affine in (x, y).
    const Vec3 n = rotation * face.normal;
    const Mat3 rt = glm::transpose(rotation);
    const Vec3 ex = rt * Vec3(1, 0, 0), ey = rt * Vec3(0, 1, 0), ez = rt * Vec3(0, 0, 1);
    const TexelFrame& tf = face.texels;
    const double inv = 1.0 / tf.size;
    const Vec3 gx = ex - ez * (n.x / n.z);   // d p / d x
    const Vec3 gy = ey - ez * (n.y / n.z);   // d p / d y
    const Vec3 p0 = ez * (face.plane_offset / n.z) - tf.origin;  // p(0,0) - origin
    PsfToTexel m;
    m.origin = Vec2(glm::dot(p0, tf.axis_u), glm::dot(p0, tf.axis_v)) * inv;
    m.dx = Vec2(glm::dot(gx, tf.axis_u), glm::dot(gx, tf.axis_v)) * inv;
    m.dy = Vec2(glm::dot(gy, tf.axis_u), glm::dot(gy, tf.axis_v)) * inv;
    return m;
}

namespace {

constexpr int kMaxPoly = 12;

struct Poly {
    Vec2 v[kMaxPoly];
    int n = 0;
};

// Splits a convex polygon by the line coord_axis = c into the part below (<= c) and the
// part above (>= c), in one Sutherland–Hodgman pass that shares the crossing points, so
// the two parts tile the polygon exactly.
template <int axis>
inline void split(const Poly& in, double c, Poly& below, Poly& above) {
    below.n = above.n = 0;
    if (in.n == 0) return;
    const Vec2* a = &in.v[in.n - 1];
    double da = (*a)[axis] - c;
    for (int k = 0; k < in.n; ++k) {
        const Vec2& b = in.v[k];
        const double db = b[axis] - c;
        if ((da < 0) != (db < 0) && da != 0 && db != 0) {
            const Vec2 x = *a + (b - *a) * (da / (da - db));
            below.v[below.n++] = x;
            above.v[above.n++] = x;
        }
        if (db <= 0) below.v[below.n++] = b;
        if (db >= 0) above.v[above.n++] = b;
        a = &b;
        da = db;
    }
}

inline double area(const Poly& p) {
    double s = 0.0;
    const Vec2* a = &p.v[p.n - 1];
    for (int k = 0; k < p.n; ++k) {
        const Vec2& b = p.v[k];
        s += a->x * b.y - a->y * b.x;
        a = &b;
    }
    return 0.5 * std::abs(s);
}

}  // namespace

int clip_quad_to_grid(const Vec2 quad[4], int width, int height, std::vector<TexelOverlap>& out) {
    // The outermost columns and rows reach to infinity: the part of a beam that spills over
    // the grid's rim lands on the rim texel, next to where it fell (like the gap a missing
    // neighbouring beam leaves there), rather than being spread over the whole footprint.
    double umin = quad[0].x, umax = quad[0].x, vmin = quad[0].y, vmax = quad[0].y;
    for (int k = 1; k < 4; ++k) {
        umin = std::min(umin, quad[k].x);
        umax = std::max(umax, quad[k].x);
        vmin = std::min(vmin, quad[k].y);
        vmax = std::max(vmax, quad[k].y);
    }
    const int i0 = std::clamp(static_cast<int>(std::floor(umin)), 0, width - 1);
    const int i1 = std::clamp(static_cast<int>(std::floor(umax)), 0, width - 1);
    const int j0 = std::clamp(static_cast<int>(std::floor(vmin)), 0, height - 1);
    const int j1 = std::clamp(static_cast<int>(std::floor(vmax)), 0, height - 1);
    const size_t before = out.size();
    Poly quadp;
    quadp.n = 4;
    for (int k = 0; k < 4; ++k) quadp.v[k] = quad[k];
    // Whole quad inside one cell: its area, no clipping (the common case when texels are
    // larger than the beam).
    if (i0 == i1 && j0 == j1) {
        const double a = area(quadp);
        if (a > 0) out.push_back({static_cast<uint32_t>(j0 * width + i0), static_cast<float>(a)});
        return static_cast<int>(out.size() - before);
    }
    // Slice column by column, then each column row by row: every cut is made once and
    // its crossing points are shared by both sides. The last column (row) of the range
    // keeps the remainder, which is also what makes the rim cells reach outwards.
    Poly rest = quadp, col, next, cell, rrest, rnext;
    for (int i = i0; i <= i1; ++i) {
        if (i < i1) {
            split<0>(rest, double(i + 1), col, next);
            rest = next;
        } else {
            col = rest;
        }
        if (col.n < 3) continue;
        rrest = col;
        for (int j = j0; j <= j1; ++j) {
            if (j < j1) {
                split<1>(rrest, double(j + 1), cell, rnext);
                rrest = rnext;
            } else {
                cell = rrest;
            }
            if (cell.n < 3) continue;
            const double a = area(cell);
            if (a > 0) out.push_back({static_cast<uint32_t>(j * width + i), static_cast<float>(a)});
        }
    }
    return static_cast<int>(out.size() - before);
}

int pixel_texel_overlaps(const PsfToTexel& map, int i, int j, int resolution, int width,
                         int height, std::vector<TexelOverlap>& out) {
    const double h = 1.0 / resolution;
    const double x = (2.0 * i + 1.0) / resolution - 1.0, y = (2.0 * j + 1.0) / resolution - 1.0;
    const Vec2 c = map(x, y);
    const Vec2 ax = map.dx * h, ay = map.dy * h;
    const Vec2 quad[4] = {c - ax - ay, c + ax - ay, c + ax + ay, c - ax + ay};
    return clip_quad_to_grid(quad, width, height, out);
}

}  // namespace vlf
