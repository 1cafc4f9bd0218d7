// smooth_groups.hpp — a scene's smooth mirror and glass surfaces: its specular faces with
// shading normals (Face::vertex_normals), grouped per (object, side, material). One group is
// one smooth surface, whatever its facets: the field carries its light per surface
// (transport/smooth_surfaces.hpp) and the walkthrough's lookup reads a point's light from
// the rays of the whole surface around it (render/render.cpp).
#pragma once

#include <vector>

#include "vlf/scene/scene.hpp"

namespace vlf {

struct SmoothGroups {
    std::vector<int> of_face;             // per face: its group, or -1 (not smooth specular)
    std::vector<std::vector<int>> faces;  // per group: its faces, ascending
};

// Groups per (object, inner, material), numbered in the order of their first faces. One
// material per group, so a group's turned light keeps one rho_s (an imported object may give
// its faces several).
SmoothGroups group_smooth_specular_faces(const Scene& scene);

}  // namespace vlf
