// scene.cpp — small queries on the scene model (DESIGN §3).
#include "vlf/scene/scene.hpp"

#include <algorithm>

namespace vlf {

int Scene::emitter_count() const {
    return static_cast<int>(std::count_if(
        faces.begin(), faces.end(), [&](const Face& f) { return material_of(f).is_emitter(); }));
}

int Scene::specular_face_count() const {
    return static_cast<int>(std::count_if(
        faces.begin(), faces.end(), [&](const Face& f) { return material_of(f).is_specular(); }));
}

}  // namespace vlf
