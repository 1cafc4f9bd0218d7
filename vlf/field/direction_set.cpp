// direction_set.cpp — the octahedral direction set: lattice, triangulation, solid angles and
// the constant-time lookups (VLF §3, §5 and §6.1; DESIGN §4; derivations in
// docs/directions.md).
#include "vlf/field/direction_set.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

constexpr int kMinLevel = 1;
constexpr int kMaxLevel = 6;

int count_for_level(int k) {
    return 2 * (1 << (2 * k)) + 1;
}

// Angle between two unit vectors, accurate for small angles too.
double angle_between(const Vec3& a, const Vec3& b) {
    return 2.0 * std::asin(std::min(1.0, glm::length(a - b) / 2.0));
}

// Solid angle of the spherical triangle (a, b, c) with great-circle edges, unit vertices
// counter-clockwise seen from outside: Van Oosterom & Strackee (1983),
// tan(Omega/2) = det(a, b, c) / (1 + a.b + b.c + c.a).
double spherical_triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double det = glm::dot(a, glm::cross(b, c));
    const double den = 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a);
    return 2.0 * std::atan2(det, den);
}

}  // namespace

std::string to_string(DirectionScheme s) {
    switch (s) {
        case DirectionScheme::Octahedral:
            return "octahedral";
        case DirectionScheme::EqualArea:
            return "equal-area";
    }
    return "octahedral";
}

DirectionScheme direction_scheme_from_string(const std::string& s) {
    if (s == "octahedral") return DirectionScheme::Octahedral;
    if (s == "equal-area") return DirectionScheme::EqualArea;
    throw ParameterError(
        fmt::format("unknown direction scheme '{}' (valid schemes: octahedral, equal-area)", s));
}

bool DirectionSet::is_valid_count(int l) {
    for (int k = kMinLevel; k <= kMaxLevel; ++k)
        if (l == count_for_level(k)) return true;
    return false;
}

std::string DirectionSet::valid_counts_text() {
    std::string text;
    for (int k = kMinLevel; k <= kMaxLevel; ++k) {
        if (!text.empty()) text += ", ";
        text += std::to_string(count_for_level(k));
    }
    return text;
}

double DirectionSet::mean_solid_angle() const {
    return 2.0 * kPi / size();
}

double DirectionSet::solid_angle_spread() const {
    const auto [lo, hi] = std::minmax_element(m_solid_angle.begin(), m_solid_angle.end());
    return *hi / *lo;
}

// --- the two maps ---------------------------------------------------------------------------

Vec3 DirectionSet::map_to_sphere(DirectionScheme scheme, const Vec2& uv) {
    const double au = std::abs(uv.x), av = std::abs(uv.y);
    const double r = au + av;
    if (scheme == DirectionScheme::Octahedral)
        return glm::normalize(Vec3(uv.x, uv.y, std::max(0.0, 1.0 - r)));
    // Equal-area octahedral map: z = 1 - r^2, azimuth within the quadrant (pi/2)|v|/r from
    // the quadrant's u axis, sin(theta) = r sqrt(2 - r^2). dOmega = pi du dv (docs/directions.md).
    if (r <= 0.0) return Vec3(0.0, 0.0, 1.0);
    const double rr = std::min(r, 1.0);
    const double phi = 0.5 * kPi * av / r;
    const double s = rr * std::sqrt(2.0 - rr * rr);
    // Exact zeros on the axes keep the lattice symmetric (cos(pi/2) is not 0 in doubles).
    const double x = au == 0.0 ? 0.0 : std::copysign(s * std::cos(phi), uv.x);
    const double y = av == 0.0 ? 0.0 : std::copysign(s * std::sin(phi), uv.y);
    return Vec3(x, y, 1.0 - rr * rr);
}

Vec2 DirectionSet::map_to_diamond(DirectionScheme scheme, const Vec3& t) {
    const double ax = std::abs(t.x), ay = std::abs(t.y), az = std::abs(t.z);
    if (scheme == DirectionScheme::Octahedral) {
        const double inv = 1.0 / (ax + ay + az);
        return Vec2(t.x * inv, t.y * inv);
    }
    // r = sqrt(1 - z), written so that it stays accurate near the pole.
    const double rho2 = ax * ax + ay * ay;
    if (rho2 <= 0.0) return Vec2(0.0, 0.0);
    const double r = std::min(1.0, std::sqrt(rho2 / (1.0 + az)));
    const double fv = std::atan2(ay, ax) * (2.0 / kPi);  // in [0, 1]
    const double v = r * fv;
    const double u = r - v;
    return Vec2(std::copysign(u, t.x), std::copysign(v, t.y));
}

// --- construction ---------------------------------------------------------------------------

DirectionSet::DirectionSet(int l, DirectionScheme scheme) : m_scheme(scheme) {
    if (!is_valid_count(l))
        throw ParameterError(fmt::format("{} is not a valid direction count (valid counts: {})", l,
                                         valid_counts_text()));
    int k = kMinLevel;
    while (count_for_level(k) != l) ++k;
    m_n = 1 << k;
    const int n = m_n;

    // Lines, row-major over j then i. The canonical representative of an antipodal pair of
    // equator points is the one with i > 0, or i == 0 and j > 0; the other one is the same
    // line travelled backwards (sense -1).
    const int side = 2 * n + 1;
    m_lattice.assign(static_cast<size_t>(side) * side, -1);
    m_lattice_sense.assign(static_cast<size_t>(side) * side, 0);
    auto canonical = [](int i, int j) { return i > 0 || (i == 0 && j > 0); };
    for (int j = -n; j <= n; ++j)
        for (int i = -n; i <= n; ++i) {
            const int r = std::abs(i) + std::abs(j);
            if (r > n || (r == n && !canonical(i, j))) continue;
            m_lattice[lattice_slot(i, j)] = static_cast<int>(m_dirs.size());
            m_lattice_sense[lattice_slot(i, j)] = 1;
            m_dirs.push_back(map_to_sphere(scheme, Vec2(double(i) / n, double(j) / n)));
        }
    for (int j = -n; j <= n; ++j)
        for (int i = -n; i <= n; ++i)
            if (std::abs(i) + std::abs(j) == n && !canonical(i, j)) {
                m_lattice[lattice_slot(i, j)] = m_lattice[lattice_slot(-i, -j)];
                m_lattice_sense[lattice_slot(i, j)] = -1;
            }
    VLF_CHECK(size() == l);

    build_triangles();

    // VLF §5: each spherical triangle gives a third of its solid angle to each vertex line.
    m_solid_angle.assign(m_dirs.size(), 0.0);
    for (const Triangle& tri : m_triangles) {
        const Vec3 a = double(tri.sense[0]) * m_dirs[tri.index[0]];
        const Vec3 b = double(tri.sense[1]) * m_dirs[tri.index[1]];
        const Vec3 c = double(tri.sense[2]) * m_dirs[tri.index[2]];
        const double third = spherical_triangle_area(a, b, c) / 3.0;
        for (int v = 0; v < 3; ++v) m_solid_angle[tri.index[v]] += third;
    }

    build_nearest_candidates();
}

Vec3 DirectionSet::travel_vector(int i, int j) const {
    const int s = lattice_slot(i, j);
    return double(m_lattice_sense[s]) * m_dirs[m_lattice[s]];
}

void DirectionSet::build_triangles() {
    const int n = m_n;
    m_cell_triangles.assign(static_cast<size_t>(2 * n) * (2 * n), {-1, -1});
    auto inside = [n](int i, int j) { return std::abs(i) + std::abs(j) <= n; };
    for (int cj = -n; cj < n; ++cj)
        for (int ci = -n; ci < n; ++ci) {
            // The diagonal is parallel to the quadrant's outer edge, so the triangles are
            // exactly the 4^k-subdivision of the octahedron faces (never straddle a face).
            const bool same_sign = (ci >= 0) == (cj >= 0);
            using Corner = std::array<int, 2>;
            const Corner p00{ci, cj}, p10{ci + 1, cj}, p01{ci, cj + 1}, p11{ci + 1, cj + 1};
            // Both halves counter-clockwise in (u, v), hence seen from outside the sphere.
            const std::array<std::array<Corner, 3>, 2> halves =
                same_sign
                    ? std::array<std::array<Corner, 3>, 2>{{{p00, p10, p01}, {p11, p01, p10}}}
                    : std::array<std::array<Corner, 3>, 2>{{{p00, p10, p11}, {p00, p11, p01}}};
            for (int h = 0; h < 2; ++h) {
                const auto& c = halves[h];
                if (!inside(c[0][0], c[0][1]) || !inside(c[1][0], c[1][1]) ||
                    !inside(c[2][0], c[2][1]))
                    continue;
                Triangle tri{};
                std::array<Vec3, 3> v;
                for (int q = 0; q < 3; ++q) {
                    const int s = lattice_slot(c[q][0], c[q][1]);
                    tri.index[q] = m_lattice[s];
                    tri.sense[q] = m_lattice_sense[s];
                    v[q] = travel_vector(c[q][0], c[q][1]);
                }
                TriangleGeometry g{};
                for (int q = 0; q < 3; ++q) {
                    g.edge[q] = glm::cross(v[(q + 1) % 3], v[(q + 2) % 3]);
                    g.inv_len[q] = 1.0 / glm::length(g.edge[q]);
                }
                m_cell_triangles[cell_slot(ci, cj)][h] = static_cast<int>(m_triangles.size());
                m_triangles.push_back(tri);
                m_geometry.push_back(g);
            }
        }
    VLF_CHECK(m_triangles.size() == static_cast<size_t>(4 * n * n));
}

// nearest(): the query maps d with the cheap octahedral map (for both schemes) to a triangle
// of the octahedral lattice map, which on the sphere is exactly the great-arc triangle with
// those vertices, so it lies in the cap (c, rho) of its vertices. For any x in the cap, the
// nearest line q satisfies dist(x, q) <= dist(x, p*) <= rho + dist(c, p*), p* the line
// nearest to c; so dist(c, q) <= 2 rho + dist(c, p*) =: R. Every line within R of c (either
// sense) is a candidate: exact, and a constant number (~11) per triangle.
void DirectionSet::build_nearest_candidates() {
    const int n = m_n;
    const int l = size();
    std::vector<int> by_z(l);
    std::iota(by_z.begin(), by_z.end(), 0);
    std::sort(by_z.begin(), by_z.end(), [&](int a, int b) { return m_dirs[a].z < m_dirs[b].z; });
    std::vector<double> zs(l);
    std::vector<Vec3> sorted(l);  // contiguous for the scans below
    for (int q = 0; q < l; ++q) {
        sorted[q] = m_dirs[by_z[q]];
        zs[q] = sorted[q].z;
    }

    // The octahedral point of each lattice position (the query's partition of the sphere).
    auto oct = [n](int i, int j) {
        return map_to_sphere(DirectionScheme::Octahedral, Vec2(double(i) / n, double(j) / n));
    };
    m_near_offset.assign(1, 0);
    m_near_offset.reserve(m_triangles.size() + 1);
    std::vector<std::pair<double, int>> found;
    for (int cj = -n; cj < n; ++cj)
        for (int ci = -n; ci < n; ++ci)
            for (int h = 0; h < 2; ++h) {
                const int id = m_cell_triangles[cell_slot(ci, cj)][h];
                if (id < 0) continue;
                VLF_CHECK(id + 1 == static_cast<int>(m_near_offset.size()));  // id order
                // Recover the triangle's lattice corners (same rule as build_triangles).
                const bool same_sign = (ci >= 0) == (cj >= 0);
                std::array<Vec3, 3> p;
                if (same_sign)
                    p = h == 0 ? std::array<Vec3, 3>{oct(ci, cj), oct(ci + 1, cj), oct(ci, cj + 1)}
                               : std::array<Vec3, 3>{oct(ci + 1, cj + 1), oct(ci, cj + 1),
                                                     oct(ci + 1, cj)};
                else
                    p = h == 0
                            ? std::array<Vec3, 3>{oct(ci, cj), oct(ci + 1, cj), oct(ci + 1, cj + 1)}
                            : std::array<Vec3, 3>{oct(ci, cj), oct(ci + 1, cj + 1),
                                                  oct(ci, cj + 1)};
                const Vec3 c = glm::normalize(p[0] + p[1] + p[2]);
                double rho = 0.0;
                for (const Vec3& q : p) rho = std::max(rho, angle_between(c, q));
                // A first radius from an upper bound of dist(c, p*): the corners of the
                // scheme's triangle under c.
                int li = 0, lj = 0;
                const Triangle& tri_ref = m_triangles[locate(map_to_diamond(m_scheme, c), li, lj)];
                double d0 = kPi;
                for (int v = 0; v < 3; ++v)
                    d0 = std::min(
                        d0, angle_between(c, double(tri_ref.sense[v]) * m_dirs[tri_ref.index[v]]));
                const double r0 = 2.0 * rho + d0 + 1e-9;
                // dist(c, +-p) >= |theta_c - theta_(+-p)|: only a band in z can qualify.
                const double theta_c = std::acos(std::clamp(c.z, -1.0, 1.0));
                const double zlo =
                    theta_c + r0 >= 0.5 * kPi ? -1.0 : std::cos(theta_c + r0) - 1e-12;
                const double zhi = theta_c - r0 <= 0.0 ? 2.0 : std::cos(theta_c - r0) + 1e-12;
                const auto first = std::lower_bound(zs.begin(), zs.end(), zlo) - zs.begin();
                const auto last = std::upper_bound(zs.begin(), zs.end(), zhi) - zs.begin();
                found.clear();
                double dstar = kPi;
                const double cos_r0 = std::cos(std::min(r0, 0.5 * kPi)) - 1e-12;
                for (auto q = first; q < last; ++q) {
                    const Vec3& d = sorted[q];
                    const double dot = glm::dot(c, d);
                    if (std::abs(dot) < cos_r0) continue;  // cheap pre-test, exact test below
                    const double ang = angle_between(c, dot >= 0.0 ? d : -d);
                    if (ang <= r0) {
                        found.emplace_back(ang, by_z[q]);
                        dstar = std::min(dstar, ang);
                    }
                }
                const double radius = 2.0 * rho + dstar + 1e-9;
                const auto begin = m_near_lines.size();
                for (const auto& [ang, idx] : found)
                    if (ang <= radius) m_near_lines.push_back(idx);
                std::sort(m_near_lines.begin() + static_cast<std::ptrdiff_t>(begin),
                          m_near_lines.end());
                m_near_offset.push_back(static_cast<int>(m_near_lines.size()));
            }
}

// --- lookups --------------------------------------------------------------------------------

int DirectionSet::locate(const Vec2& uv, int& ci, int& cj) const {
    const int n = m_n;
    const double fu = uv.x * n, fv = uv.y * n;
    ci = std::clamp(static_cast<int>(std::floor(fu)), -n, n - 1);
    cj = std::clamp(static_cast<int>(std::floor(fv)), -n, n - 1);
    // Points on (or, by rounding, just outside) the diamond boundary: step the cell inwards
    // until its corner nearest the origin is inside the diamond.
    auto inner = [](int c) { return std::abs(c >= 0 ? c : c + 1); };
    while (inner(ci) + inner(cj) >= n) {
        if (inner(ci) >= inner(cj))
            ci += ci >= 0 ? -1 : 1;
        else
            cj += cj >= 0 ? -1 : 1;
    }
    const double a = fu - ci, b = fv - cj;
    const bool same_sign = (ci >= 0) == (cj >= 0);
    const int half = same_sign ? (a + b <= 1.0 ? 0 : 1) : (b <= a ? 0 : 1);
    const auto& cell = m_cell_triangles[cell_slot(ci, cj)];
    return cell[half] >= 0 ? cell[half] : cell[1 - half];
}

int DirectionSet::nearest(const Vec3& d) const {
    VLF_DCHECK(std::abs(glm::dot(d, d) - 1.0) < 1e-6);
    const Vec3 up = d.z < 0.0 ? -d : d;
    int ci = 0, cj = 0;
    const int tri = locate(map_to_diamond(DirectionScheme::Octahedral, up), ci, cj);
    int best = -1;
    double best_dot = -1.0;
    for (int q = m_near_offset[tri]; q < m_near_offset[tri + 1]; ++q) {
        const int idx = m_near_lines[q];
        const double c = std::abs(glm::dot(d, m_dirs[idx]));
        if (c > best_dot) {
            best_dot = c;
            best = idx;
        }
    }
    return best;
}

EnclosingTriangle DirectionSet::enclosing(const Vec3& t) const {
    int hint = -1;
    return enclosing(t, hint);
}

EnclosingTriangle DirectionSet::enclosing(const Vec3& t, int& hint) const {
    VLF_DCHECK(std::abs(glm::dot(t, t) - 1.0) < 1e-6);
    // The triangulation covers the upper hemisphere; a downward t is found as -t in the
    // triangle with all senses flipped (the gnomonic weights are unchanged by the flip).
    const bool flip = t.z < 0.0;
    const Vec3 up = flip ? -t : t;
    // The least signed distance of up from a triangle's edges (great circles): positive
    // inside it. The triangles tile the hemisphere, neighbours sharing each edge's great
    // circle, so a point inside one by more than rounding (at a vertex the triangles around
    // it all score about +-1e-17) is inside no other: the map's triangle or its search below
    // would find the same one.
    constexpr double kInside = 1e-9;
    auto score = [&](int id) {
        const TriangleGeometry& g = m_geometry[id];
        double s = std::numeric_limits<double>::max();
        for (int q = 0; q < 3; ++q) s = std::min(s, glm::dot(up, g.edge[q]) * g.inv_len[q]);
        return s;
    };
    int tri = hint;
    if (tri < 0 || tri >= int(m_triangles.size()) || !(score(tri) > kInside)) {
        int ci = 0, cj = 0;
        tri = locate(map_to_diamond(m_scheme, up), ci, cj);
        if (score(tri) < 0.0) {
            // The map triangle does not contain t on the sphere: for the octahedral scheme
            // only by rounding, for the equal-area one because its curved edges differ from
            // great arcs. The true triangle touches the map triangle: search the 3x3 cells
            // around.
            double best = score(tri);
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int ni = ci + di, nj = cj + dj;
                    if (ni < -m_n || ni >= m_n || nj < -m_n || nj >= m_n) continue;
                    for (int id : m_cell_triangles[cell_slot(ni, nj)]) {
                        if (id < 0) continue;
                        const double s = score(id);
                        if (s > best) {
                            best = s;
                            tri = id;
                        }
                    }
                }
        }
    }
    hint = tri;
    const Triangle& tr = m_triangles[tri];
    const TriangleGeometry& g = m_geometry[tri];
    EnclosingTriangle e;
    double sum = 0.0;
    for (int q = 0; q < 3; ++q) {
        e.index[q] = tr.index[q];
        e.sense[q] = flip ? -tr.sense[q] : tr.sense[q];
        // Gnomonic barycentrics: t = sum w_q v_q / |...| with w_a = det(t, b, c) etc.
        e.weight[q] = std::max(0.0, glm::dot(up, g.edge[q]));
        sum += e.weight[q];
    }
    if (sum > 0.0) {
        for (double& w : e.weight) w /= sum;
    } else {
        e.weight = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
    }
    return e;
}

}  // namespace vlf
