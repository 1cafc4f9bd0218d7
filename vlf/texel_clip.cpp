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

// Sutherland–Hodgman against the half-plane sign*(coord_axis - c) >= 0.
inline void clip(const Poly& in, Poly& out, int axis, double c, double sign) {
    out.n = 0;
    if (in.n == 0) return;
    for (int k = 0; k < in.n; ++k) {
        const Vec2& a = in.v[k];
        const Vec2& b = in.v[(k + 1) % in.n];
        const double da = sign * (a[axis] - c), db = sign * (b[axis] - c);
        if (da >= 0) out.v[out.n++] = a;
        if ((da >= 0) != (db >= 0)) {
            const double t = da / (da - db);
            out.v[out.n++] = a + (b - a) * t;
        }
    }
}

inline double area(const Poly& p) {
    double s = 0.0;
    for (int k = 0; k < p.n; ++k) {
        const Vec2& a = p.v[k];
        const Vec2& b = p.v[(k + 1) % p.n];
        s += a.x * b.y - a.y * b.x;
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
    Poly col, tmp, cell, tmp2;
    for (int i = i0; i <= i1; ++i) {
        const Poly* c = &quadp;
        if (i > 0) {
            clip(*c, tmp, 0, double(i), 1.0);
            c = &tmp;
        }
        if (i < width - 1) {
            clip(*c, col, 0, double(i + 1), -1.0);
        } else {
            col = *c;
        }
        if (col.n < 3) continue;
        for (int j = j0; j <= j1; ++j) {
            const Poly* r = &col;
            if (j > 0) {
                clip(*r, tmp2, 1, double(j), 1.0);
                r = &tmp2;
            }
            if (j < height - 1) {
                clip(*r, cell, 1, double(j + 1), -1.0);
            } else {
                cell = *r;
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
