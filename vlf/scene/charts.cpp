// charts.cpp — region growing of charts over shared edges (charts.hpp).
#include "vlf/scene/charts.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/scene/texel_frame.hpp"

namespace vlf {

namespace {

// One directed edge of a face, keyed by its two end points (ordered) so that the two faces
// of a shared edge sort next to each other.
struct EdgeRef {
    uint64_t key;
    int face;
    int edge;
};

bool less_point(const Vec3& a, const Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
}

// The two end points of edge e of f, lower first.
std::pair<Vec3, Vec3> ends(const Face& f, int e) {
    const Vec3& a = f.vertices[e];
    const Vec3& b = f.vertices[(size_t(e) + 1) % f.vertices.size()];
    return less_point(a, b) ? std::pair{a, b} : std::pair{b, a};
}

// Per face edge (offset[f] + e): the neighbouring face across it, or -1. A neighbour runs
// the edge the other way, has the same material and a normal within `cos_max` of the
// face's; an edge with more than one such candidate has none.
std::vector<int> find_neighbours(const std::vector<Face>& faces, const std::vector<size_t>& offset,
                                 double cos_max) {
    std::vector<EdgeRef> edges(offset.back());
    parallel_for(0, static_cast<long>(faces.size()), [&](long fi) {
        const Face& f = faces[fi];
        for (int e = 0; e < int(f.vertices.size()); ++e) {
            const auto [a, b] = ends(f, e);
            edges[offset[fi] + e] = {position_hash(a) * 31 ^ position_hash(b), f.id, e};
        }
    });
    // A total order (key, face, edge): the parallel sort gives the one result.
    tbb::parallel_sort(edges.begin(), edges.end(), [](const EdgeRef& x, const EdgeRef& y) {
        return std::tie(x.key, x.face, x.edge) < std::tie(y.key, y.face, y.edge);
    });
    std::vector<int> out(offset.back(), -1);
    for (size_t lo = 0; lo < edges.size();) {
        size_t hi = lo + 1;
        while (hi < edges.size() && edges[hi].key == edges[lo].key) ++hi;
        for (size_t i = lo; i < hi; ++i) {
            const Face& f = faces[edges[i].face];
            if (edges[i].edge < 64 && (f.cut_edges >> edges[i].edge & 1u)) continue;
            const Vec3& fa = f.vertices[edges[i].edge];
            int found = -1, count = 0;
            for (size_t j = lo; j < hi; ++j) {
                if (j == i) continue;
                const Face& g = faces[edges[j].face];
                if (g.id == f.id || g.material != f.material) continue;
                if (ends(f, edges[i].edge) != ends(g, edges[j].edge)) continue;  // hash clash
                if (!(g.vertices[edges[j].edge] != fa)) continue;  // same direction: not a seam
                if (glm::dot(f.normal, g.normal) < cos_max) continue;
                found = g.id;
                ++count;
            }
            if (count == 1) out[offset[f.id] + edges[i].edge] = found;
        }
        lo = hi;
    }
    return out;
}

Vec3 mean_normal(const Chart& c, const std::vector<Face>& faces) {
    Vec3 sum(0.0);
    for (int f : c.faces) sum += faces[f].normal * faces[f].area;
    const double l = glm::length(sum);
    return l > 0 ? sum / l : faces[c.faces[0]].normal;
}

// A chart of less than `min_area` (a texel) is too small to own rays: on a crease of a
// curved mesh its slivers would bake black. It joins the neighbouring chart whose normal
// is nearest its own, if every one of its faces lies within kMergeAngleDeg of that
// normal. Charts are then renumbered in order of their first face.
void merge_small_charts(Scene& scene, const std::vector<int>& neighbour,
                        const std::vector<size_t>& offset, double min_area) {
    std::vector<Face>& faces = scene.faces;
    std::vector<Chart>& charts = scene.charts;
    const double cos_merge = std::cos(kMergeAngleDeg * kPi / 180.0);
    for (Chart& s : charts) {
        double area = 0.0;
        for (int f : s.faces) area += faces[f].area;
        if (area >= min_area || s.faces.empty()) continue;
        const Vec3 ns = mean_normal(s, faces);
        int best = -1;
        double best_dot = -2.0;
        for (int f : s.faces)
            for (size_t e = 0; e < faces[f].vertices.size(); ++e) {
                const int g = neighbour[offset[f] + e];
                if (g < 0 || faces[g].chart == s.id) continue;
                const Chart& t = charts[faces[g].chart];
                const Vec3 nt = mean_normal(t, faces);
                bool fits = true;
                for (int h : s.faces) fits = fits && glm::dot(faces[h].normal, nt) >= cos_merge;
                const double d = glm::dot(ns, nt);
                if (fits && (d > best_dot || (d == best_dot && t.id < best))) {
                    best = t.id;
                    best_dot = d;
                }
            }
        if (best < 0) continue;
        for (int f : s.faces) faces[f].chart = best;
        charts[best].faces.insert(charts[best].faces.end(), s.faces.begin(), s.faces.end());
        s.faces.clear();
    }
    std::vector<Chart> kept;
    for (Chart& c : charts) {
        if (c.faces.empty()) continue;
        std::sort(c.faces.begin(), c.faces.end());
        c.id = static_cast<int>(kept.size());
        for (int f : c.faces) faces[f].chart = c.id;
        kept.push_back(std::move(c));
    }
    std::sort(kept.begin(), kept.end(),
              [](const Chart& a, const Chart& b) { return a.faces[0] < b.faces[0]; });
    for (size_t k = 0; k < kept.size(); ++k) {
        kept[k].id = static_cast<int>(k);
        for (int f : kept[k].faces) faces[f].chart = kept[k].id;
    }
    charts = std::move(kept);
}

}  // namespace

void build_charts(Scene& scene, double texel_size, int max_texels_per_side, double max_angle_deg) {
    std::vector<Face>& faces = scene.faces;
    const size_t nf = faces.size();
    std::vector<size_t> offset(nf + 1, 0);
    for (size_t f = 0; f < nf; ++f) offset[f + 1] = offset[f] + faces[f].vertices.size();
    const double cos_max = std::cos(max_angle_deg * kPi / 180.0);
    const double cos_merge = std::cos(kMergeAngleDeg * kPi / 180.0);
    const std::vector<int> neighbour =
        max_angle_deg > 0 ? find_neighbours(faces, offset, std::min(cos_max, cos_merge))
                          : std::vector<int>(offset.back(), -1);

    scene.charts.clear();
    for (Face& f : faces) f.chart = -1, f.inner_edges = 0;
    std::deque<int> queue;
    for (size_t seed = 0; seed < nf; ++seed) {
        if (faces[seed].chart >= 0) continue;
        Chart c;
        c.id = static_cast<int>(scene.charts.size());
        c.material = faces[seed].material;
        const Vec3 n0 = faces[seed].normal;
        faces[seed].chart = c.id;
        queue.push_back(int(seed));
        while (!queue.empty()) {
            const int f = queue.front();
            queue.pop_front();
            c.faces.push_back(f);
            for (size_t e = 0; e < faces[f].vertices.size(); ++e) {
                const int g = neighbour[offset[f] + e];
                if (g < 0 || faces[g].chart >= 0) continue;
                if (glm::dot(faces[g].normal, n0) < cos_max) continue;
                faces[g].chart = c.id;
                queue.push_back(g);
            }
        }
        scene.charts.push_back(std::move(c));
    }
    if (max_angle_deg > 0) merge_small_charts(scene, neighbour, offset, texel_size * texel_size);
    for (Face& f : faces)
        for (size_t e = 0; e < f.vertices.size() && e < 64; ++e) {
            const int g = neighbour[offset[f.id] + e];
            if (g >= 0 && faces[g].chart == f.chart) f.inner_edges |= uint64_t(1) << e;
        }
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long k) {
        Chart& c = scene.charts[k];
        Vec3 sum(0.0);
        c.area = 0.0;
        c.planar = true;
        for (int f : c.faces) {
            sum += faces[f].normal * faces[f].area;
            c.area += faces[f].area;
            c.planar = c.planar && faces[f].normal == faces[c.faces[0]].normal;
        }
        c.normal = c.planar ? faces[c.faces[0]].normal : glm::normalize(sum);
        finish_chart(c, faces);
        build_chart_texels(c, faces, texel_size, max_texels_per_side);
    });
}

void finish_chart(Chart& c, const std::vector<Face>& faces) {
    c.area_normal = Vec3(0.0);
    c.min_cos = 1.0;
    for (int f : c.faces) {
        c.area_normal += faces[f].area * faces[f].normal;
        c.min_cos = std::min(c.min_cos, glm::dot(faces[f].normal, c.normal));
    }
}

}  // namespace vlf
