// closed_surface.cpp — closedness of a polygon soup (closed_surface.hpp).
#include "vlf/scene/closed_surface.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>
#include <unordered_map>

namespace vlf {

namespace {

// Welds points within tol: a grid of cells of size tol, a point looks in its 27 cells.
class Welder {
  public:
    explicit Welder(double tol) : m_tol(tol) {}
    int id(const Vec3& p) {
        const auto key = cell(p);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = m_cells.find(
                        {std::get<0>(key) + dx, std::get<1>(key) + dy, std::get<2>(key) + dz});
                    if (it == m_cells.end()) continue;
                    for (int v : it->second)
                        if (glm::length(m_points[size_t(v)] - p) <= m_tol) return v;
                }
        const int v = static_cast<int>(m_points.size());
        m_points.push_back(p);
        m_cells[key].push_back(v);
        return v;
    }
    const Vec3& point(int v) const { return m_points[size_t(v)]; }

  private:
    using Key = std::tuple<int64_t, int64_t, int64_t>;
    Key cell(const Vec3& p) const {
        return {int64_t(std::floor(p.x / m_tol)), int64_t(std::floor(p.y / m_tol)),
                int64_t(std::floor(p.z / m_tol))};
    }
    double m_tol;
    std::vector<Vec3> m_points;
    std::map<Key, std::vector<int>> m_cells;
};

}  // namespace

std::optional<std::string> open_edge(const std::vector<Polygon>& polygons, double tol) {
    Welder weld(tol > 0 ? tol : 1e-12);
    std::map<std::pair<int, int>, int> directed;  // a -> b: how many polygons run it
    for (const Polygon& p : polygons)
        for (size_t k = 0; k < p.size(); ++k) {
            const int a = weld.id(p[k]), b = weld.id(p[(k + 1) % p.size()]);
            if (a != b) ++directed[{a, b}];
        }
    auto where = [&](int a, int b) {
        const Vec3 &x = weld.point(a), &y = weld.point(b);
        return fmt::format("({:.6g}, {:.6g}, {:.6g})-({:.6g}, {:.6g}, {:.6g})", x.x, x.y, x.z, y.x,
                           y.y, y.z);
    };
    for (const auto& [edge, count] : directed) {
        const auto [a, b] = edge;
        const auto back = directed.find({b, a});
        const int reverse = back == directed.end() ? 0 : back->second;
        if (count > 1)
            return fmt::format(
                "edge {} is run the same way by {} faces (a face turned over, or "
                "more than two faces on one edge)",
                where(a, b), count);
        if (reverse == 0)
            return fmt::format("edge {} belongs to one face only (a hole, or a T-junction)",
                               where(a, b));
    }
    // Closed and consistent: the faces turn outward when they enclose a positive volume
    // (divergence theorem: V = 1/3 sum over faces of x.n A, each polygon fanned from its
    // first corner).
    double volume = 0.0;
    for (const Polygon& p : polygons)
        for (size_t k = 1; k + 1 < p.size(); ++k)
            volume += glm::dot(p[0], glm::cross(p[k], p[k + 1])) / 6.0;
    if (!(volume > 0.0))
        return fmt::format(
            "its faces turn inward (they enclose a volume of {:.6g}: a flipped box, or a mesh "
            "wound the other way)",
            volume);
    return std::nullopt;
}

}  // namespace vlf
