#include "vlf/scene/sealed_areas.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "vlf/scene/texel_frame.hpp"

namespace vlf {

void subtract_sealed_areas(Scene& scene, double gap) {
    std::vector<std::vector<double>> before(scene.charts.size());
    for (Chart& c : scene.charts) c.texel_open.clear();
    // Faces grouped by orientation (normals equal to 1e-6), each group sorted by offset.
    std::map<std::tuple<long, long, long>, std::vector<int>> groups;
    for (const Face& f : scene.faces)
        groups[{std::lround(f.normal.x * 1e6), std::lround(f.normal.y * 1e6),
                std::lround(f.normal.z * 1e6)}]
            .push_back(f.id);
    for (auto& [key, ids] : groups) {
        std::sort(ids.begin(), ids.end(), [&](int a, int b) {
            return std::tie(scene.faces[a].plane_offset, a) <
                   std::tie(scene.faces[b].plane_offset, b);
        });
        for (size_t i = 0; i < ids.size(); ++i) {
            const Face& f = scene.faces[ids[i]];
            Chart& chart = scene.charts[f.chart];
            const TexelFrame& tf = chart.texels;
            for (size_t j = i + 1; j < ids.size(); ++j) {
                const Face& g = scene.faces[ids[j]];
                const double d = g.plane_offset - f.plane_offset;
                if (d > gap) break;
                if (d <= 0.0) continue;  // coplanar: not in front
                const std::vector<Vec2> covered = intersect_convex(
                    polygon_in_texels(tf, g.vertices), polygon_in_texels(tf, f.vertices));
                if (covered.empty()) continue;
                double lo_u = covered[0].x, hi_u = lo_u, lo_v = covered[0].y, hi_v = lo_v;
                for (const Vec2& p : covered) {
                    lo_u = std::min(lo_u, p.x), hi_u = std::max(hi_u, p.x);
                    lo_v = std::min(lo_v, p.y), hi_v = std::max(hi_v, p.y);
                }
                const double cell = tf.size * tf.size * projected_area_scale(chart, f);
                const int i0 = std::max(0, int(std::floor(lo_u))),
                          i1 = std::min(tf.width - 1, int(std::floor(hi_u)));
                const int j0 = std::max(0, int(std::floor(lo_v))),
                          j1 = std::min(tf.height - 1, int(std::floor(hi_v)));
                if (before[size_t(chart.id)].empty()) before[size_t(chart.id)] = chart.texel_area;
                for (int v = j0; v <= j1; ++v)
                    for (int u = i0; u <= i1; ++u) {
                        double& a = chart.texel_area[size_t(v) * tf.width + u];
                        const double cut =
                            clipped_area(covered, Vec2(u, v), Vec2(u + 1, v + 1)) * cell;
                        a = std::max(0.0, a - cut);
                    }
            }
        }
    }
    // The open part of each texel of the charts that lost any (receive_step.cpp).
    for (Chart& c : scene.charts) {
        const std::vector<double>& full = before[size_t(c.id)];
        if (full.empty()) continue;
        c.texel_open.resize(full.size());
        for (size_t k = 0; k < full.size(); ++k)
            c.texel_open[k] = full[k] > 0 ? std::clamp(c.texel_area[k] / full[k], 0.0, 1.0) : 1.0;
    }
}

}  // namespace vlf
