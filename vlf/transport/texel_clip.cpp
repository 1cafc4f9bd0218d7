#include "vlf/transport/texel_clip.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/parallel.hpp"
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
void fold_to_grid(const P& piece, int depth, const std::vector<RimLine>& rim, int width, int height,
                  std::vector<TexelOverlap>& out) {
    const int n = static_cast<int>(rim.size());
    P ia, ib, right, image;
    const P* inside = &piece;
    P* inside_out = &ia;
    P* inside_spare = &ib;
    for (int e = 0; e < n && inside->size() >= 3; ++e) {
        const Vec2& a = rim[e].a;
        const Vec2& b = rim[e].b;
        split_by_edge(*inside, a, b, *inside_out, right);
        inside = inside_out;
        std::swap(inside_out, inside_spare);
        if (depth >= kMaxFolds || right.size() < 3 || area(right) <= 0.0) continue;
        image.clear();
        for (int k = 0; k < right.size(); ++k) image.push(reflect(right[k], a, b - a));
        fold_to_grid(image, depth + 1, rim, width, height, out);
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

int clip_footprint_to_grid(const Vec2 quad[4], const std::vector<RimLine>& rim, int width,
                           int height, std::vector<TexelOverlap>& out) {
    const size_t before = out.size();
    // Whole quad inside the rim (the interior of a face): no clipping.
    bool whole = true;
    const int n = static_cast<int>(rim.size());
    for (int e = 0; e < n && whole; ++e) {
        const Vec2& a = rim[e].a;
        const Vec2 d = rim[e].b - a;
        for (int k = 0; k < 4; ++k)
            whole = whole && d.x * (quad[k].y - a.y) - d.y * (quad[k].x - a.x) >= 0;
    }
    if (whole) return clip_quad_to_grid(quad, width, height, out);
    // A quad (4) cut by n edges once per fold, then by grid lines (+8).
    constexpr int kSmallEdges = 8;
    if (n <= kSmallEdges) {
        SmallPoly<4 + (kMaxFolds + 1) * kSmallEdges + 8> q;
        for (int k = 0; k < 4; ++k) q.push(quad[k]);
        fold_to_grid(q, 0, rim, width, height, out);
    } else {
        BigPoly q;
        for (int k = 0; k < 4; ++k) q.push(quad[k]);
        fold_to_grid(q, 0, rim, width, height, out);
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

std::vector<RimLine> polygon_rim(const std::vector<Vec2>& polygon) {
    std::vector<RimLine> rim(polygon.size());
    for (size_t e = 0; e < polygon.size(); ++e)
        rim[e] = {polygon[e], polygon[(e + 1) % polygon.size()]};
    return rim;
}

namespace {

// A face's own rim: its edges not shared inside its chart, in its chart's texel
// coordinates, counter-clockwise (reversed with the polygon if the winding turned).
std::vector<RimLine> own_rim(const Face& face, const TexelFrame& grid) {
    const size_t n = face.vertices.size();
    std::vector<Vec2> p;
    p.reserve(n);
    for (const Vec3& v : face.vertices) p.push_back(grid.to_texel(v));
    double twice_area = 0.0;
    for (size_t k = 0; k < n; ++k)
        twice_area += p[k].x * p[(k + 1) % n].y - p[k].y * p[(k + 1) % n].x;
    std::vector<RimLine> rim;
    for (size_t e = 0; e < n; ++e) {
        if (e < 64 && (face.inner_edges >> e & 1u)) continue;
        const Vec2 &a = p[e], &b = p[(e + 1) % n];
        rim.push_back(twice_area < 0 ? RimLine{b, a} : RimLine{a, b});
    }
    if (twice_area < 0) std::reverse(rim.begin(), rim.end());
    return rim;
}

// A face in a chart takes at most this many of its chart's rim lines besides its own edges:
// a straight rim is one line, a corner two; a curved rim's nearest few stand for it.
constexpr size_t kMaxRimLines = 6;

// The two lines are one (same direction, the same offset), to rounding.
bool same_line(const RimLine& x, const RimLine& y) {
    const Vec2 dx = x.b - x.a, dy = y.b - y.a;
    const double lx = glm::length(dx), ly = glm::length(dy);
    if (!(lx > 0) || !(ly > 0)) return false;
    if (glm::dot(dx, dy) < (1 - 1e-9) * lx * ly) return false;
    const Vec2 w = y.a - x.a;
    return std::abs(dx.x * w.y - dx.y * w.x) <= 1e-9 * lx * std::max(1.0, glm::length(w));
}

// Squared distance between the axis-aligned boxes of two point sets.
double box_gap2(const Vec2& lo1, const Vec2& hi1, const Vec2& lo2, const Vec2& hi2) {
    const double gx = std::max(0.0, std::max(lo1.x - hi2.x, lo2.x - hi1.x));
    const double gy = std::max(0.0, std::max(lo1.y - hi2.y, lo2.y - hi1.y));
    return gx * gx + gy * gy;
}

// Adds to each face of chart c the rim lines of the chart within `reach` of it. The rim
// pieces are bucketed on a grid of cell `reach`, so a face looks only at its neighbourhood.
void add_chart_rim(const Scene& scene, const Chart& c, double reach_normalised,
                   std::vector<FaceInTexels>& out) {
    const double reach = reach_normalised / c.texels.size;  // in texels
    std::vector<RimLine> rim;
    for (int f : c.faces) rim.insert(rim.end(), out[f].rim.begin(), out[f].rim.end());
    if (rim.empty()) return;
    const double cell = std::max(reach, 1e-9);
    const int gw = std::max(1, int(std::ceil(c.texels.width / cell)) + 2);
    const int gh = std::max(1, int(std::ceil(c.texels.height / cell)) + 2);
    auto bucket = [&](double x, int size) {
        return std::clamp(int(std::floor(x / cell)) + 1, 0, size - 1);
    };
    std::vector<std::vector<uint32_t>> grid(size_t(gw) * gh);
    for (uint32_t r = 0; r < rim.size(); ++r) {
        const Vec2 lo = glm::min(rim[r].a, rim[r].b), hi = glm::max(rim[r].a, rim[r].b);
        for (int y = bucket(lo.y, gh); y <= bucket(hi.y, gh); ++y)
            for (int x = bucket(lo.x, gw); x <= bucket(hi.x, gw); ++x)
                grid[size_t(y) * gw + x].push_back(r);
    }
    std::vector<uint32_t> seen;
    std::vector<std::pair<double, uint32_t>> near;
    std::vector<Vec2> corners;
    for (int f : c.faces) {
        Vec2 lo(1e300), hi(-1e300);
        corners.clear();
        for (const Vec3& v : scene.faces[f].vertices) {
            corners.push_back(c.texels.to_texel(v));
            lo = glm::min(lo, corners.back());
            hi = glm::max(hi, corners.back());
        }
        seen.clear();
        for (int y = bucket(lo.y - reach, gh); y <= bucket(hi.y + reach, gh); ++y)
            for (int x = bucket(lo.x - reach, gw); x <= bucket(hi.x + reach, gw); ++x)
                for (uint32_t r : grid[size_t(y) * gw + x]) seen.push_back(r);
        std::sort(seen.begin(), seen.end());
        seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
        // The nearest lines first; a face is clipped at no more than kMaxRimLines of them.
        near.clear();
        for (uint32_t r : seen) {
            const RimLine& line = rim[r];
            const double gap = box_gap2(lo, hi, glm::min(line.a, line.b), glm::max(line.a, line.b));
            if (gap > reach * reach) continue;
            // A line whose extension cuts the face (a bend of a curved rim, a concave
            // corner) is no rim for it: the face lies inside every line it is clipped at.
            const Vec2 d = line.b - line.a;
            const double tol = 1e-9 * glm::length(d) * std::max(1.0, glm::length(hi - lo));
            bool inside = true;
            for (const Vec2& corner : corners) {
                const Vec2 p = corner - line.a;
                inside = inside && d.x * p.y - d.y * p.x >= -tol;
            }
            if (inside) near.push_back({gap, r});
        }
        std::sort(near.begin(), near.end());
        std::vector<RimLine>& mine = out[f].rim;
        const size_t cap = mine.size() + kMaxRimLines;
        for (const auto& [gap, r] : near) {
            if (mine.size() >= cap) break;
            if (std::none_of(mine.begin(), mine.end(),
                             [&](const RimLine& m) { return same_line(m, rim[r]); }))
                mine.push_back(rim[r]);
        }
    }
}

}  // namespace

std::vector<FaceInTexels> faces_in_texels(const Scene& scene, double reach) {
    std::vector<FaceInTexels> out(scene.faces.size());
    parallel_for(0, static_cast<long>(scene.faces.size()), [&](long f) {
        out[f].rim = own_rim(scene.faces[f], scene.chart_of(scene.faces[f]).texels);
    });
    // The own rims are complete before any chart copies them.
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long c) {
        // A flat chart's rim is a few straight lines that every face near it shares; a
        // curved chart's rim bends every edge, and its faces keep their own rim edges.
        const Chart& chart = scene.charts[c];
        if (chart.faces.size() > 1 && chart.min_cos >= 1.0 - 1e-9)
            add_chart_rim(scene, chart, reach, out);
    });
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
    return clip_footprint_to_grid(quad, face.rim, width, height, out);
}

}  // namespace vlf
