#include "vlf/transport/texel_clip.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/scene/texel_frame.hpp"

namespace vlf {

PsfToTexel psf_to_texel(const Face& face, const TexelFrame& tf, const Mat3& rotation) {
    // Rotated-frame point on the plane: q = (x, y, z(x, y)), z = (D - n.x x - n.y y) / n.z,
    // scene point p = R^T q, texel = ((p - o).au, (p - o).av) / size. All affine in (x, y).
    const Vec3 n = rotation * face.normal;
    const Mat3 rt = glm::transpose(rotation);
    const Vec3 ex = rt * Vec3(1, 0, 0), ey = rt * Vec3(0, 1, 0), ez = rt * Vec3(0, 0, 1);
    const double inv = 1.0 / tf.size;
    const Vec3 gx = ex - ez * (n.x / n.z);                       // d p / d x
    const Vec3 gy = ey - ez * (n.y / n.z);                       // d p / d y
    const Vec3 p0 = ez * (face.plane_offset / n.z) - tf.origin;  // p(0,0) - origin
    PsfToTexel m;
    m.origin = Vec2(glm::dot(p0, tf.axis_u), glm::dot(p0, tf.axis_v)) * inv;
    m.dx = Vec2(glm::dot(gx, tf.axis_u), glm::dot(gx, tf.axis_v)) * inv;
    m.dy = Vec2(glm::dot(gy, tf.axis_u), glm::dot(gy, tf.axis_v)) * inv;
    return m;
}

namespace {

// A convex polygon of at most Cap vertices, on the stack: the common case (a beam's
// parallelogram cut by at most a few polygon edges, then by grid lines).
template <int Cap>
struct SmallPoly {
    Vec2 v[Cap];
    int n = 0;
    SmallPoly() = default;
    // Copies only the vertices in use (the capacity is far larger than the common case).
    SmallPoly(const SmallPoly& o) : n(o.n) { std::copy(o.v, o.v + o.n, v); }
    SmallPoly& operator=(const SmallPoly& o) {
        n = o.n;
        std::copy(o.v, o.v + o.n, v);
        return *this;
    }
    void clear() { n = 0; }
    void push(const Vec2& p) { v[n++] = p; }
    int size() const { return n; }
    const Vec2& operator[](int k) const { return v[k]; }
};

// The same on the heap, for footprints cut by many polygon edges (a small face of many
// vertices under a large beam).
struct BigPoly {
    std::vector<Vec2> v;
    void clear() { v.clear(); }
    void push(const Vec2& p) { v.push_back(p); }
    int size() const { return static_cast<int>(v.size()); }
    const Vec2& operator[](int k) const { return v[k]; }
};

// Splits a convex polygon by the line coord_axis = c into the part below (<= c) and the
// part above (>= c), in one Sutherland–Hodgman pass that shares the crossing points, so
// the two parts tile the polygon exactly.
template <int axis, class P>
inline void split(const P& in, double c, P& below, P& above) {
    below.clear();
    above.clear();
    if (in.size() == 0) return;
    const Vec2* a = &in[in.size() - 1];
    double da = (*a)[axis] - c;
    for (int k = 0; k < in.size(); ++k) {
        const Vec2& b = in[k];
        const double db = b[axis] - c;
        if ((da < 0) != (db < 0) && da != 0 && db != 0) {
            const Vec2 x = *a + (b - *a) * (da / (da - db));
            below.push(x);
            above.push(x);
        }
        if (db <= 0) below.push(b);
        if (db >= 0) above.push(b);
        a = &b;
        da = db;
    }
}

template <class P>
inline double area(const P& p) {
    double s = 0.0;
    const Vec2* a = &p[p.size() - 1];
    for (int k = 0; k < p.size(); ++k) {
        const Vec2& b = p[k];
        s += a->x * b.y - a->y * b.x;
        a = &b;
    }
    return 0.5 * std::abs(s);
}

// Slices a convex polygon into the cells of the grid (rim cells unbounded outwards).
template <class P>
void slice_to_grid(const P& poly, int width, int height, std::vector<TexelOverlap>& out) {
    if (poly.size() < 3) return;
    double umin = poly[0].x, umax = poly[0].x, vmin = poly[0].y, vmax = poly[0].y;
    for (int k = 1; k < poly.size(); ++k) {
        umin = std::min(umin, poly[k].x);
        umax = std::max(umax, poly[k].x);
        vmin = std::min(vmin, poly[k].y);
        vmax = std::max(vmax, poly[k].y);
    }
    const int i0 = std::clamp(static_cast<int>(std::floor(umin)), 0, width - 1);
    const int i1 = std::clamp(static_cast<int>(std::floor(umax)), 0, width - 1);
    const int j0 = std::clamp(static_cast<int>(std::floor(vmin)), 0, height - 1);
    const int j1 = std::clamp(static_cast<int>(std::floor(vmax)), 0, height - 1);
    // Whole polygon inside one cell: its area, no clipping (the common case when texels
    // are larger than the beam).
    if (i0 == i1 && j0 == j1) {
        const double a = area(poly);
        if (a > 0) out.push_back({static_cast<uint32_t>(j0 * width + i0), static_cast<float>(a)});
        return;
    }
    // Slice column by column, then each column row by row: every cut is made once and
    // its crossing points are shared by both sides. The last column (row) of the range
    // keeps the remainder, which is also what makes the rim cells reach outwards. The
    // remainders alternate between two buffers (no copies).
    P col, cell, ca, cb, ra, rb;
    const P* rest = &poly;
    P* rest_out = &ca;
    P* rest_spare = &cb;
    for (int i = i0; i <= i1; ++i) {
        const P* column = rest;
        if (i < i1) {
            split<0>(*rest, double(i + 1), col, *rest_out);
            rest = rest_out;
            std::swap(rest_out, rest_spare);
            column = &col;
        }
        if (column->size() < 3) continue;
        const P* rrest = column;
        P* row_out = &ra;
        P* row_spare = &rb;
        for (int j = j0; j <= j1; ++j) {
            const P* c = rrest;
            if (j < j1) {
                split<1>(*rrest, double(j + 1), cell, *row_out);
                rrest = row_out;
                std::swap(row_out, row_spare);
                c = &cell;
            }
            if (c->size() < 3) continue;
            const double a = area(*c);
            if (a > 0) out.push_back({static_cast<uint32_t>(j * width + i), static_cast<float>(a)});
        }
    }
}

// Splits a convex polygon by the directed line a -> b into its left part (inside a
// counter-clockwise polygon's edge) and its right part, sharing the crossing points.
template <class P>
inline void split_by_edge(const P& in, const Vec2& a, const Vec2& b, P& left, P& right) {
    left.clear();
    right.clear();
    if (in.size() == 0) return;
    const Vec2 e = b - a;
    auto side = [&](const Vec2& p) { return e.x * (p.y - a.y) - e.y * (p.x - a.x); };
    const Vec2* p = &in[in.size() - 1];
    double dp = side(*p);
    for (int k = 0; k < in.size(); ++k) {
        const Vec2& q = in[k];
        const double dq = side(q);
        if ((dp < 0) != (dq < 0) && dp != 0 && dq != 0) {
            const Vec2 x = *p + (q - *p) * (dp / (dp - dq));
            left.push(x);
            right.push(x);
        }
        if (dq >= 0) left.push(q);
        if (dq <= 0) right.push(q);
        p = &q;
        dp = dq;
    }
}

// Mirror image of a point in the line through a with direction e.
inline Vec2 reflect(const Vec2& p, const Vec2& a, const Vec2& e) {
    const Vec2 d = p - a;
    const Vec2 along = e * (glm::dot(d, e) / glm::dot(e, e));
    return a + along - (d - along);
}

// Mirror images of a spilled part fold back at most this often (a part beyond two edges
// near a corner needs two reflections, as an image source does in a wedge).
constexpr int kMaxFolds = 3;

// Appends the overlaps of (piece ∩ polygon) with the grid; each part of the piece beyond an
// edge (and inside the edges before it) is mirrored back across that edge and folded in
// the same way. See clip_footprint_to_grid in the header for why.
template <class P>
void fold_to_grid(const P& piece, int depth, const std::vector<Vec2>& polygon, uint64_t inner,
                  int width, int height, std::vector<TexelOverlap>& out) {
    const int n = static_cast<int>(polygon.size());
    P ia, ib, right, image;
    const P* inside = &piece;
    P* inside_out = &ia;
    P* inside_spare = &ib;
    for (int e = 0; e < n && inside->size() >= 3; ++e) {
        if (e < 64 && (inner >> e & 1u)) continue;  // the chart goes on: no rim here
        const Vec2& a = polygon[e];
        const Vec2& b = polygon[(e + 1) % n];
        split_by_edge(*inside, a, b, *inside_out, right);
        inside = inside_out;
        std::swap(inside_out, inside_spare);
        if (depth >= kMaxFolds || right.size() < 3 || area(right) <= 0.0) continue;
        image.clear();
        for (int k = 0; k < right.size(); ++k) image.push(reflect(right[k], a, b - a));
        fold_to_grid(image, depth + 1, polygon, inner, width, height, out);
    }
    if (inside->size() >= 3) slice_to_grid(*inside, width, height, out);
}

}  // namespace

int clip_quad_to_grid(const Vec2 quad[4], int width, int height, std::vector<TexelOverlap>& out) {
    const size_t before = out.size();
    SmallPoly<12> q;  // a quad cut by grid lines stays within 12 vertices
    for (int k = 0; k < 4; ++k) q.push(quad[k]);
    slice_to_grid(q, width, height, out);
    return static_cast<int>(out.size() - before);
}

int clip_footprint_to_grid(const Vec2 quad[4], const std::vector<Vec2>& polygon, uint64_t inner,
                           int width, int height, std::vector<TexelOverlap>& out) {
    const size_t before = out.size();
    // Whole quad inside the polygon (the interior of a face): no polygon clipping.
    bool whole = true;
    const int n = static_cast<int>(polygon.size());
    for (int e = 0; e < n && whole; ++e) {
        if (e < 64 && (inner >> e & 1u)) continue;
        const Vec2& a = polygon[e];
        const Vec2 d = polygon[(e + 1) % n] - a;
        for (int k = 0; k < 4; ++k)
            whole = whole && d.x * (quad[k].y - a.y) - d.y * (quad[k].x - a.x) >= 0;
    }
    if (whole) return clip_quad_to_grid(quad, width, height, out);
    // A quad (4) cut by n edges once per fold, then by grid lines (+8).
    constexpr int kSmallEdges = 8;
    if (n <= kSmallEdges) {
        SmallPoly<4 + (kMaxFolds + 1) * kSmallEdges + 8> q;
        for (int k = 0; k < 4; ++k) q.push(quad[k]);
        fold_to_grid(q, 0, polygon, inner, width, height, out);
    } else {
        BigPoly q;
        for (int k = 0; k < 4; ++k) q.push(quad[k]);
        fold_to_grid(q, 0, polygon, inner, width, height, out);
    }
    // The same texel can be reached by the direct part and by mirrored parts: merge.
    for (size_t i = before; i < out.size(); ++i)
        for (size_t j = i + 1; j < out.size();) {
            if (out[j].texel == out[i].texel) {
                out[i].area += out[j].area;
                out[j] = out.back();
                out.pop_back();
            } else {
                ++j;
            }
        }
    return static_cast<int>(out.size() - before);
}

FaceInTexels face_in_texels(const Face& face, const TexelFrame& chart) {
    FaceInTexels out;
    const size_t n = face.vertices.size();
    out.polygon.reserve(n);
    for (const Vec3& v : face.vertices) out.polygon.push_back(chart.to_texel(v));
    double twice_area = 0.0;
    for (size_t k = 0; k < n; ++k) {
        const Vec2& a = out.polygon[k];
        const Vec2& b = out.polygon[(k + 1) % n];
        twice_area += a.x * b.y - a.y * b.x;
    }
    out.inner = face.inner_edges;
    if (twice_area < 0) {
        // Reversed, edge e (e -> e+1) becomes edge n-2-e (mod n): polygon_in_texels' order.
        std::reverse(out.polygon.begin(), out.polygon.end());
        out.inner = 0;
        for (size_t e = 0; e < n && e < 64; ++e)
            if (face.inner_edges >> e & 1u) {
                const size_t r = (2 * n - 2 - e) % n;
                if (r < 64) out.inner |= uint64_t(1) << r;
            }
    }
    return out;
}

int pixel_texel_overlaps(const PsfToTexel& map, int i, int j, int resolution,
                         const FaceInTexels& face, int width, int height,
                         std::vector<TexelOverlap>& out) {
    const double h = 1.0 / resolution;
    const double x = (2.0 * i + 1.0) / resolution - 1.0, y = (2.0 * j + 1.0) / resolution - 1.0;
    const Vec2 c = map(x, y);
    const Vec2 ax = map.dx * h, ay = map.dy * h;
    const Vec2 quad[4] = {c - ax - ay, c + ax - ay, c + ax + ay, c - ax + ay};
    return clip_footprint_to_grid(quad, face.polygon, face.inner, width, height, out);
}

}  // namespace vlf
