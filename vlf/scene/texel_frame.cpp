// texel_frame.cpp — texel grids and exact texel ∩ polygon areas.
#include "vlf/scene/texel_frame.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

// Keeps the part of `in` on the side sign*(x[axis] - bound) >= 0.
void clip(const std::vector<Vec2>& in, std::vector<Vec2>& out, int axis, double bound,
          double sign) {
    out.clear();
    const size_t m = in.size();
    if (m == 0) return;
    for (size_t i = 0; i < m; ++i) {
        const Vec2& a = in[i];
        const Vec2& b = in[(i + 1) % m];
        const double da = sign * (a[axis] - bound);
        const double db = sign * (b[axis] - bound);
        if (da >= 0) out.push_back(a);
        if ((da >= 0) != (db >= 0)) {
            const double t = da / (da - db);
            Vec2 x = a + t * (b - a);
            x[axis] = bound;  // exactly on the clip line
            out.push_back(x);
        }
    }
}

double shoelace(const std::vector<Vec2>& p) {
    const size_t m = p.size();
    if (m < 3) return 0.0;
    double s = 0;
    for (size_t i = 0; i < m; ++i) {
        const Vec2& a = p[i];
        const Vec2& b = p[(i + 1) % m];
        s += a.x * b.y - a.y * b.x;
    }
    return 0.5 * s;
}

}  // namespace

double clipped_area(const std::vector<Vec2>& poly, const Vec2& lo, const Vec2& hi) {
    std::vector<Vec2> a = poly, b;
    clip(a, b, 0, lo.x, +1);
    clip(b, a, 0, hi.x, -1);
    clip(a, b, 1, lo.y, +1);
    clip(b, a, 1, hi.y, -1);
    return std::abs(shoelace(a));
}

std::vector<Vec2> polygon_in_texels(const TexelFrame& frame, const std::vector<Vec3>& vertices) {
    std::vector<Vec2> p;
    p.reserve(vertices.size());
    for (const Vec3& v : vertices) p.push_back(frame.to_texel(v));
    if (shoelace(p) < 0) std::reverse(p.begin(), p.end());
    return p;
}

std::vector<Vec2> intersect_convex(std::vector<Vec2> subject, const std::vector<Vec2>& clip) {
    std::vector<Vec2> out;
    for (size_t e = 0; e < clip.size() && subject.size() >= 3; ++e) {
        const Vec2 a = clip[e], d = clip[(e + 1) % clip.size()] - a;
        auto side = [&](const Vec2& p) { return d.x * (p.y - a.y) - d.y * (p.x - a.x); };
        out.clear();
        for (size_t k = 0; k < subject.size(); ++k) {
            const Vec2& p = subject[k];
            const Vec2& q = subject[(k + 1) % subject.size()];
            const double sp = side(p), sq = side(q);
            if (sp >= 0) out.push_back(p);
            if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
        }
        subject.swap(out);
    }
    return subject.size() >= 3 ? subject : std::vector<Vec2>{};
}

namespace {

// The direction of axis_u in the chart's plane: the direction along which its rim (the
// edges not shared inside the chart; every edge of a single face) is longest in total, so
// a polygon cut into triangles gets the grid of the polygon.
// Of two rim directions equally long in total, the canonical one: the larger x, then y, then
// z, so the grid does not depend on where a polygon's vertex list starts or how a surface
// is cut.
bool canonical_before(const Vec3& a, const Vec3& b) {
    constexpr double eps = 1e-9;
    for (int c = 0; c < 3; ++c)
        if (std::abs(a[c] - b[c]) > eps) return a[c] > b[c];
    return false;
}

Vec3 chart_axis_u(const Chart& chart, const std::vector<Face>& faces) {
    const Vec3 n = chart.normal;
    auto in_plane = [&](const Vec3& e) { return e - n * glm::dot(e, n); };
    constexpr size_t kMaxGroups = 64;
    std::vector<std::pair<Vec3, double>> groups;  // unit direction, total rim length
    Vec3 longest_edge(0.0);
    double longest = -1;
    for (int fi : chart.faces) {
        const Face& f = faces[fi];
        const size_t m = f.vertices.size();
        for (size_t e = 0; e < m; ++e) {
            if (e < 64 && (f.inner_edges >> e & 1u)) continue;
            const Vec3 d = in_plane(f.vertices[(e + 1) % m] - f.vertices[e]);
            const double l = glm::length(d);
            if (!(l > 0)) continue;
            if (l > longest) longest = l, longest_edge = d;
            const Vec3 u = d / l;
            auto g = std::find_if(groups.begin(), groups.end(),
                                  [&](const auto& x) { return glm::dot(x.first, u) > 1.0 - 1e-9; });
            if (g != groups.end())
                g->second += l;
            else if (groups.size() < kMaxGroups)
                groups.push_back({u, l});
        }
    }
    if (groups.empty() || groups.size() >= kMaxGroups)
        return glm::normalize(longest_edge);  // a curved rim: its longest edge
    auto best = groups.begin();
    for (auto g = groups.begin() + 1; g != groups.end(); ++g) {
        const double tie = 1e-9 * std::max(g->second, best->second);
        if (g->second > best->second + tie ||
            (g->second >= best->second - tie && canonical_before(g->first, best->first)))
            best = g;
    }
    return best->first;
}

// Calls add(texel, area) with the area of the polygon q (texel coordinates) in each texel
// it covers, in texel units. Each
// row is clipped once, then each column inside the row's strip; the outermost rows and
// columns are not clipped on their outer side, so rounding at the bounding rectangle
// cannot lose area.
template <class Add>
void for_polygon_area(const std::vector<Vec2>& q, const TexelFrame& f, Add&& add) {
    double qmin = std::numeric_limits<double>::infinity(), qmax = -qmin;
    for (const Vec2& x : q) qmin = std::min(qmin, x.y), qmax = std::max(qmax, x.y);
    const int r0 = std::clamp(static_cast<int>(std::floor(qmin)), 0, f.height - 1);
    const int r1 = std::clamp(static_cast<int>(std::floor(qmax)), 0, f.height - 1);
    std::vector<Vec2> strip, tmp, cell, tmp2;
    for (int j = r0; j <= r1; ++j) {
        strip = q;
        if (j > 0) clip(strip, tmp, 1, j, +1), std::swap(strip, tmp);
        if (j < f.height - 1) clip(strip, tmp, 1, j + 1, -1), std::swap(strip, tmp);
        if (strip.size() < 3) continue;
        double smin = std::numeric_limits<double>::infinity(), smax = -smin;
        for (const Vec2& x : strip) smin = std::min(smin, x.x), smax = std::max(smax, x.x);
        const int i0 = std::clamp(static_cast<int>(std::floor(smin)), 0, f.width - 1);
        const int i1 = std::clamp(static_cast<int>(std::floor(smax)), 0, f.width - 1);
        for (int i = i0; i <= i1; ++i) {
            cell = strip;
            if (i > 0) clip(cell, tmp2, 0, i, +1), std::swap(cell, tmp2);
            if (i < f.width - 1) clip(cell, tmp2, 0, i + 1, -1), std::swap(cell, tmp2);
            add(static_cast<size_t>(j) * f.width + i, std::abs(shoelace(cell)));
        }
    }
}

}  // namespace

double projected_area_scale(const Chart& chart, const Face& face) {
    if (face.normal == chart.normal) return 1.0;
    return 1.0 / std::max(1e-6, glm::dot(face.normal, chart.normal));
}

void face_texel_areas(const Chart& chart, const Face& face, std::vector<TexelArea>& out) {
    const TexelFrame& f = chart.texels;
    std::vector<Vec2> q;
    for (const Vec3& v : face.vertices) q.push_back(f.to_texel(v));
    const double scale = f.size * f.size * projected_area_scale(chart, face);
    for_polygon_area(q, f, [&](size_t t, double a) {
        if (a > 0) out.push_back({static_cast<uint32_t>(t), a * scale});
    });
}

void build_chart_texels(Chart& chart, const std::vector<Face>& faces, double texel_size,
                        int max_texels_per_side) {
    VLF_CHECK(!chart.faces.empty());
    VLF_CHECK(texel_size > 0 && std::isfinite(texel_size));
    VLF_CHECK(max_texels_per_side >= 1);
    const Vec3 n = chart.normal;
    const Vec3 u = chart_axis_u(chart, faces);
    const Vec3 v = glm::normalize(glm::cross(n, u));

    double umin = std::numeric_limits<double>::infinity(), vmin = umin;
    double umax = -umin, vmax = -umin;
    for (int fi : chart.faces)
        for (const Vec3& x : faces[fi].vertices) {
            const double a = glm::dot(x, u), b = glm::dot(x, v);
            umin = std::min(umin, a), umax = std::max(umax, a);
            vmin = std::min(vmin, b), vmax = std::max(vmax, b);
        }
    const double eu = umax - umin, ev = vmax - vmin;

    double size = texel_size;
    const double longest_extent = std::max(eu, ev);
    if (longest_extent / size > max_texels_per_side) size = longest_extent / max_texels_per_side;
    auto cells = [&](double extent) {
        // A face that is a whole number of texels wide must not get a sliver column from
        // rounding: 1e-6 of a texel is far below any geometric feature.
        return std::max(1, static_cast<int>(std::ceil(extent / size - 1e-6)));
    };
    // ceil() of a quotient that rounds up past the cap: grow the size by an ulp-scale step.
    while (cells(eu) > max_texels_per_side || cells(ev) > max_texels_per_side) size *= 1 + 1e-12;

    const Face& seed = faces[chart.faces[0]];
    TexelFrame& f = chart.texels;
    f.axis_u = u;
    f.axis_v = v;
    f.origin = n * glm::dot(n, seed.vertices[0]) + umin * u + vmin * v;
    if (chart.faces.size() == 1) f.origin = n * seed.plane_offset + umin * u + vmin * v;
    f.size = size;
    f.width = cells(eu);
    f.height = cells(ev);

    chart.texel_area.assign(static_cast<size_t>(f.width) * f.height, 0.0);
    std::vector<Vec2> q;
    for (int fi : chart.faces) {
        const Face& face = faces[fi];
        q.resize(face.vertices.size());
        for (size_t i = 0; i < q.size(); ++i)
            q[i] = {(glm::dot(face.vertices[i], u) - umin) / size,
                    (glm::dot(face.vertices[i], v) - vmin) / size};
        const double scale = size * size * projected_area_scale(chart, face);
        for_polygon_area(q, f, [&](size_t t, double a) { chart.texel_area[t] += a * scale; });
    }
}

}  // namespace vlf
