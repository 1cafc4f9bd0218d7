// direction_set.hpp — the l line directions of the light field on the upper hemisphere,
// with constant-time nearest-direction and enclosing-triangle lookups (VLF §3 and [10];
// Wyman et al. §5.2 for barycentric interpolation between three directions; DESIGN §4).
//
// Construction: the upper half of the octahedron, each of its 4 faces subdivided into
// 4^k triangles (edge split into n = 2^k segments). In the octahedral map the vertices are
// the lattice points (i/n, j/n) with |i|+|j| <= n; antipodal equator points (i,j) and
// (-i,-j), |i|+|j| = n, are the same line and counted once, which gives l = 2*4^k + 1
// (9, 33, 129, 513, 2049, 8193 for k = 1..6).
//
// Two schemes share the lattice and triangulation and differ in the map from the
// lattice to the sphere:
//  * Octahedral: radial projection of the octahedron (the paper's kind of scheme);
//  * EqualArea:  an equal-area octahedral map (z = 1 - r^2, r = |u|+|v|), so every
//                lattice triangle of the map covers the same solid angle.
//
// Each line direction carries light both ways; a *travel* direction t is the line
// direction d(i) with sense +1 (t = d) or -1 (t = -d).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

enum class DirectionScheme { Octahedral, EqualArea };

std::string to_string(DirectionScheme s);
DirectionScheme direction_scheme_from_string(const std::string& s);  // throws ParameterError

struct EnclosingTriangle {
    std::array<int, 3> index{};      // line directions (indices into the set)
    std::array<int, 3> sense{};      // +1: travel = direction(index), -1: travel = -direction
    std::array<double, 3> weight{};  // >= 0, sum to 1 (gnomonic / spherical barycentric)
};

class DirectionSet {
  public:
    // l must be 2*4^k + 1, k = 1..6; anything else throws ParameterError.
    DirectionSet(int l, DirectionScheme scheme = DirectionScheme::Octahedral);

    static bool is_valid_count(int l);
    static std::string valid_counts_text();  // "9, 33, 129, 513, 2049, 8193"

    int size() const { return static_cast<int>(m_dirs.size()); }
    int subdivisions() const { return m_n; }  // n = 2^k
    DirectionScheme scheme() const { return m_scheme; }
    const Vec3& direction(int i) const { return m_dirs[i]; }  // unit, z >= 0
    double solid_angle(int i) const { return m_solid_angle[i]; }
    double mean_solid_angle() const;    // 2*pi / l
    double solid_angle_spread() const;  // max / min over all directions

    // Nearest line direction to a unit vector (its sign ignored): argmax_i |dot(d, d_i)|.
    // Constant time.
    int nearest(const Vec3& d) const;
    // The spherical triangle of the triangulation that contains the *travel* direction t
    // (any unit vector), its vertices as (line index, sense) and barycentric weights.
    // Constant time.
    EnclosingTriangle enclosing(const Vec3& t) const;
    // The same, trying first the triangle `hint` names (the one the caller's previous
    // direction fell in, or -1), which is taken when t lies inside it by more than rounding
    // (not on an edge or at a vertex, where the map decides); `hint` is
    // set to t's triangle. Neighbouring directions (a curved mirror's reflections of
    // neighbouring rays) skip the map and its search; the result is the same.
    EnclosingTriangle enclosing(const Vec3& t, int& hint) const;

    // The triangles of the hemisphere triangulation (each vertex as line index + sense).
    struct Triangle {
        std::array<int, 3> index;
        std::array<int, 3> sense;
    };
    const std::vector<Triangle>& triangles() const { return m_triangles; }

  private:
    friend struct DirectionSetTestAccess;  // tests/direction_set_test.cpp: the two maps

    // Per triangle: the three edge-plane normals in travel-vector orientation, so that
    // dot(t, edge[k]) = det(t, v_{k+1}, v_{k+2}) is the unnormalised gnomonic barycentric of
    // vertex k, and inv_len[k] = 1/|edge[k]| turns it into the sine of t's distance to the
    // great circle of the opposite edge (positive inside).
    struct TriangleGeometry {
        std::array<Vec3, 3> edge;
        std::array<double, 3> inv_len;
    };

    // Lattice (u, v) in the diamond |u|+|v| <= 1 -> point on the upper hemisphere, and back
    // (t.z >= 0). Octahedral: radial projection; EqualArea: z = 1 - r^2, r = |u|+|v|.
    static Vec3 map_to_sphere(DirectionScheme scheme, const Vec2& uv);
    static Vec2 map_to_diamond(DirectionScheme scheme, const Vec3& t);

    int lattice_slot(int i, int j) const { return (j + m_n) * (2 * m_n + 1) + (i + m_n); }
    int cell_slot(int ci, int cj) const { return (cj + m_n) * (2 * m_n) + (ci + m_n); }
    // The cell (ci, cj) in [-n, n-1]^2 and the half (0/1) of the lattice triangle under the
    // diamond point uv (clamped into the diamond); returns the triangle id.
    int locate(const Vec2& uv, int& ci, int& cj) const;
    Vec3 travel_vector(int lattice_i, int lattice_j) const;
    void build_triangles();
    void build_nearest_candidates();

    int m_n = 0;
    DirectionScheme m_scheme;
    std::vector<Vec3> m_dirs;
    std::vector<double> m_solid_angle;
    std::vector<Triangle> m_triangles;
    std::vector<int> m_lattice;  // (2n+1)^2 entries: lattice (i,j) -> line index (or -1)
    std::vector<signed char> m_lattice_sense;          // +1, or -1 at non-canonical equator points
    std::vector<std::array<int, 2>> m_cell_triangles;  // (2n)^2 cells x 2 halves -> id or -1
    std::vector<TriangleGeometry> m_geometry;          // per triangle
    // nearest(): per triangle of the *octahedral* lattice map, every line that can be the
    // nearest one for some direction inside it (CSR: offsets into m_near_lines).
    std::vector<int> m_near_offset;
    std::vector<int> m_near_lines;
};

}  // namespace vlf
