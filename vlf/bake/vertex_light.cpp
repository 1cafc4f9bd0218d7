// vertex_light.cpp — the gathered light of a face at a point (vertex_light.hpp).
#include "vlf/bake/vertex_light.hpp"

#include <algorithm>

namespace vlf {

size_t VertexLight::face_count() const {
    return size_t(std::count_if(first.begin(), first.end(), [](int64_t i) { return i >= 0; }));
}

Rgb VertexLight::at(const Face& f, const Vec3& x) const {
    thread_local std::vector<double> w;
    polygon_weights(f.vertices, f.normal, x, w);
    const RgbF* v = incident.data() + first[size_t(f.id)];
    Rgb out(0.0);
    for (size_t i = 0; i < w.size(); ++i) out += w[i] * Rgb(v[i]);
    // Just outside the face (a primary ray's hit on its rim) the weights extrapolate.
    return glm::max(out, Rgb(0.0));
}

}  // namespace vlf
