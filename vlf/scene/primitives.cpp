// primitives.cpp — shape generators and polygon checks (DESIGN §3).
#include "vlf/scene/primitives.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <utility>

namespace vlf {

// ---- shape generators -----------------------------------------------------------------

std::vector<Polygon> make_box(const Vec3& lo, const Vec3& hi) {
    const double x0 = lo.x, y0 = lo.y, z0 = lo.z, x1 = hi.x, y1 = hi.y, z1 = hi.z;
    // Each quad is counter-clockwise seen from outside (checked by primitives_test).
    return {
        {{x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}},  // -x
        {{x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}},  // +x
        {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}},  // -y
        {{x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}},  // +y
        {{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}},  // -z
        {{x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}},  // +z
    };
}

std::vector<Polygon> make_icosphere(const Vec3& center, double radius, int subdivisions) {
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> unit = {
        {-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
        {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1},
    };
    for (Vec3& v : unit) v = glm::normalize(v);
    using Tri = std::array<int, 3>;
    std::vector<Tri> tris = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1},
    };
    for (int level = 0; level < subdivisions; ++level) {
        // One midpoint per edge, shared by both triangles, so shared edges stay watertight.
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            unit.push_back(glm::normalize(unit[key.first] + unit[key.second]));
            int id = static_cast<int>(unit.size()) - 1;
            midpoint.emplace(key, id);
            return id;
        };
        std::vector<Tri> next;
        next.reserve(tris.size() * 4);
        for (const Tri& t : tris) {
            int a = mid(t[0], t[1]), b = mid(t[1], t[2]), c = mid(t[2], t[0]);
            next.push_back({t[0], a, c});
            next.push_back({t[1], b, a});
            next.push_back({t[2], c, b});
            next.push_back({a, b, c});
        }
        tris = std::move(next);
    }
    std::vector<Vec3> pos(unit.size());
    for (size_t i = 0; i < unit.size(); ++i) pos[i] = center + radius * unit[i];
    std::vector<Polygon> out;
    out.reserve(tris.size());
    for (const Tri& t : tris) {
        Polygon p = {pos[t[0]], pos[t[1]], pos[t[2]]};
        // The base list is outward; keep the guarantee explicit and cheap.
        if (glm::dot(newell_vector(p), unit[t[0]] + unit[t[1]] + unit[t[2]]) < 0)
            std::reverse(p.begin(), p.end());
        out.push_back(std::move(p));
    }
    return out;
}

std::vector<Polygon> make_cylinder(const CylinderShape& s) {
    const int n = s.segments;
    std::vector<double> c(n), sn(n);
    for (int k = 0; k < n; ++k) {
        double a = 2.0 * kPi * k / n;
        c[k] = std::cos(a);
        sn[k] = std::sin(a);
    }
    const Vec3 b = s.base_center;
    const Vec3 top = b + Vec3(0, s.height, 0);
    auto ring = [&](double r, double y, int k) {
        return Vec3(b.x + r * c[k % n], b.y + y, b.z + r * sn[k % n]);
    };
    const double ro = s.radius, ri = s.inner_radius, h = s.height;
    std::vector<Polygon> out;
    for (int k = 0; k < n; ++k)  // outer wall, facing out
        out.push_back({ring(ro, 0, k), ring(ro, h, k), ring(ro, h, k + 1), ring(ro, 0, k + 1)});
    if (ri > 0)
        for (int k = 0; k < n; ++k)  // inner wall, facing the axis
            out.push_back({ring(ri, 0, k), ring(ri, 0, k + 1), ring(ri, h, k + 1), ring(ri, h, k)});
    if (s.caps) {
        if (ri > 0) {
            for (int k = 0; k < n; ++k)  // bottom annulus, facing -y
                out.push_back(
                    {ring(ri, 0, k), ring(ro, 0, k), ring(ro, 0, k + 1), ring(ri, 0, k + 1)});
            for (int k = 0; k < n; ++k)  // top annulus, facing +y
                out.push_back(
                    {ring(ri, h, k), ring(ri, h, k + 1), ring(ro, h, k + 1), ring(ro, h, k)});
        } else {
            for (int k = 0; k < n; ++k) out.push_back({b, ring(ro, 0, k), ring(ro, 0, k + 1)});
            for (int k = 0; k < n; ++k) out.push_back({top, ring(ro, h, k + 1), ring(ro, h, k)});
        }
    }
    return out;
}

// ---- smooth shading normals ---------------------------------------------------------------

VertexNormals sphere_normals(const std::vector<Polygon>& faces, const Vec3& center) {
    VertexNormals out(faces.size());
    for (size_t k = 0; k < faces.size(); ++k)
        for (const Vec3& v : faces[k]) out[k].push_back(glm::normalize(v - center));
    return out;
}

VertexNormals cylinder_normals(const std::vector<Polygon>& faces, const CylinderShape& s) {
    VertexNormals out(faces.size());
    const size_t walls = size_t(s.segments) * (s.inner_radius > 0 ? 2 : 1);
    for (size_t k = 0; k < faces.size() && k < walls; ++k) {
        // Face order: the outer wall's `segments` quads, then the inner wall's.
        const double side = k < size_t(s.segments) ? 1.0 : -1.0;
        for (const Vec3& v : faces[k]) {
            const Vec3 radial(v.x - s.base_center.x, 0.0, v.z - s.base_center.z);
            out[k].push_back(side * glm::normalize(radial));
        }
    }
    return out;
}

// ---- polygon geometry ---------------------------------------------------------------------

Vec3 polygon_centroid(const Polygon& p) {
    Vec3 c(0.0);
    for (const Vec3& v : p) c += v;
    return p.empty() ? c : c / static_cast<double>(p.size());
}

Vec3 newell_vector(const Polygon& p) {
    // Newell's method relative to the centroid (same vector, less cancellation far from
    // the origin).
    const Vec3 c = polygon_centroid(p);
    Vec3 n(0.0);
    const size_t m = p.size();
    for (size_t i = 0; i < m; ++i) n += glm::cross(p[i] - c, p[(i + 1) % m] - c);
    return n;
}

double polygon_area(const Polygon& p) {
    return 0.5 * glm::length(newell_vector(p));
}

double max_plane_deviation(const Polygon& p) {
    const Vec3 nv = newell_vector(p);
    const double len = glm::length(nv);
    if (!(len > 0)) return std::numeric_limits<double>::infinity();
    const Vec3 n = nv / len;
    const Vec3 c = polygon_centroid(p);
    double dev = 0;
    for (const Vec3& v : p) dev = std::max(dev, std::abs(glm::dot(v - c, n)));
    return dev;
}

namespace {

// An orthonormal basis (u, v) of the plane with normal n, u x v = n.
void plane_basis(const Vec3& n, Vec3& u, Vec3& v) {
    const Vec3 a = std::abs(n.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    u = glm::normalize(a - n * glm::dot(a, n));
    v = glm::cross(n, u);
}

double cross2(const Vec2& a, const Vec2& b) {
    return a.x * b.y - a.y * b.x;
}

}  // namespace

std::optional<std::string> polygon_problem(const Polygon& p, double planar_tolerance,
                                           double eps_length) {
    const size_t m = p.size();
    if (m < 3) return fmt::format("polygon has {} vertices (needs at least 3)", m);
    for (size_t i = 0; i < m; ++i)
        if (glm::length(p[(i + 1) % m] - p[i]) <= eps_length)
            return fmt::format("polygon is degenerate (vertices {} and {} coincide)", i,
                               (i + 1) % m);
    const Vec3 nv = newell_vector(p);
    const double area = 0.5 * glm::length(nv);
    if (!(area > eps_length * eps_length))
        return fmt::format("polygon is degenerate (area {:.3g})", area);
    const double dev = max_plane_deviation(p);
    if (dev > planar_tolerance)
        return fmt::format("polygon is not planar (max deviation {:.3g} from its plane)", dev);
    // Convexity: every turn is counter-clockwise (or straight) about the normal, and the
    // turns add up to one full winding (rules out stars, which turn the right way twice).
    const Vec3 n = nv / (2 * area);
    double winding = 0;
    for (size_t i = 0; i < m; ++i) {
        const Vec3 e0 = p[i] - p[(i + m - 1) % m];
        const Vec3 e1 = p[(i + 1) % m] - p[i];
        const double s = glm::dot(glm::cross(e0, e1), n);
        const double cosine = glm::dot(e0, e1);
        if (s < -1e-9 * glm::length(e0) * glm::length(e1))
            return fmt::format("polygon is not convex (turns clockwise at vertex {})", i);
        winding += std::atan2(s, cosine);
    }
    if (std::abs(winding - 2 * kPi) > 1e-6)
        return fmt::format("polygon is not convex (its outline winds {:.3g} times)",
                           winding / (2 * kPi));
    return std::nullopt;
}

std::optional<std::vector<Polygon>> triangulate_polygon(const Polygon& p, double planar_tolerance,
                                                        double eps_length) {
    std::vector<Polygon> out;
    const size_t m = p.size();
    const double min_area = eps_length * eps_length;
    auto emit = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        Polygon t = {a, b, c};
        if (polygon_area(t) > min_area) out.push_back(std::move(t));
    };
    if (m < 3) return out;
    const Vec3 nv = newell_vector(p);
    const double len = glm::length(nv);
    if (!(len > 0)) {
        // Zero net area: collinear points (every triangle degenerate, all dropped) or an
        // outline whose lobes cancel (a bow tie), which crosses itself.
        for (size_t i = 1; i + 1 < m; ++i) emit(p[0], p[i], p[i + 1]);
        if (!out.empty()) return std::nullopt;
        return out;
    }
    if (max_plane_deviation(p) > planar_tolerance) {
        // Non-planar: a fan from vertex 0, as documented.
        for (size_t i = 1; i + 1 < m; ++i) emit(p[0], p[i], p[i + 1]);
        return out;
    }
    // Planar: ear clipping in the polygon's own plane, counter-clockwise about its normal.
    Vec3 u, v;
    plane_basis(nv / len, u, v);
    std::vector<Vec2> q(m);
    for (size_t i = 0; i < m; ++i) q[i] = {glm::dot(p[i], u), glm::dot(p[i], v)};
    // An outline that crosses itself has no triangulation with its orientation: two edges
    // that do not share a vertex must not properly intersect.
    for (size_t i = 0; i < m; ++i)
        for (size_t j = i + 2; j < m; ++j) {
            if (i == 0 && j == m - 1) continue;  // adjacent through the closing edge
            const Vec2 a = q[i], b = q[(i + 1) % m], c = q[j], d = q[(j + 1) % m];
            const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
            const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
            if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) &&
                ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
                return std::nullopt;
        }
    std::vector<int> idx(m);
    for (size_t i = 0; i < m; ++i) idx[i] = static_cast<int>(i);
    auto inside = [&](const Vec2& x, const Vec2& a, const Vec2& b, const Vec2& c) {
        return cross2(b - a, x - a) >= 0 && cross2(c - b, x - b) >= 0 && cross2(a - c, x - c) >= 0;
    };
    while (idx.size() > 3) {
        const size_t k = idx.size();
        bool clipped = false;
        for (size_t i = 0; i < k && !clipped; ++i) {
            const int ia = idx[(i + k - 1) % k], ib = idx[i], ic = idx[(i + 1) % k];
            const Vec2 a = q[ia], b = q[ib], c = q[ic];
            const double turn = cross2(b - a, c - b);
            if (turn < 0) continue;  // reflex
            bool ear = true;
            if (turn > 0) {
                for (int j : idx) {
                    if (j == ia || j == ib || j == ic) continue;
                    if (q[j] == a || q[j] == b || q[j] == c) continue;
                    if (inside(q[j], a, b, c)) {
                        ear = false;
                        break;
                    }
                }
            }
            // A straight vertex (turn == 0) is clipped as a zero-area ear and dropped.
            if (ear) {
                emit(p[ia], p[ib], p[ic]);
                idx.erase(idx.begin() + static_cast<std::ptrdiff_t>(i));
                clipped = true;
            }
        }
        if (!clipped) return std::nullopt;
    }
    emit(p[idx[0]], p[idx[1]], p[idx[2]]);
    return out;
}

}  // namespace vlf
