// smooth_groups.cpp — grouping a scene's smooth specular faces into surfaces
// (smooth_groups.hpp).
#include "vlf/scene/smooth_groups.hpp"

#include <map>
#include <tuple>

namespace vlf {

SmoothGroups group_smooth_specular_faces(const Scene& scene) {
    SmoothGroups g;
    g.of_face.assign(scene.faces.size(), -1);
    std::map<std::tuple<int, bool, int>, int> index;
    for (const Face& f : scene.faces) {
        if (f.vertex_normals.empty() || !scene.material_of(f).is_specular()) continue;
        const auto [at, added] =
            index.try_emplace({f.object, f.inner, f.material}, int(g.faces.size()));
        if (added) g.faces.emplace_back();
        g.of_face[size_t(f.id)] = at->second;
        g.faces[size_t(at->second)].push_back(f.id);
    }
    return g;
}

}  // namespace vlf
