// scene.cpp — small queries on the scene model (DESIGN §3).
#include "vlf/scene/scene.hpp"

#include <algorithm>

namespace vlf {

Rgb Scene::albedo_at(const Face& f, const Vec3& x, double footprint) const {
    const Material& m = material_of(f);
    if (m.diffuse_texture < 0 || f.uv.size() != 3) return m.diffuse;
    // Barycentric coordinates of x in the triangle (x lies on its plane).
    const Vec3 e1 = f.vertices[1] - f.vertices[0], e2 = f.vertices[2] - f.vertices[0];
    const Vec3 d = x - f.vertices[0];
    const double a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
    const double p = glm::dot(d, e1), q = glm::dot(d, e2);
    const double det = a * c - b * b;
    if (!(det > 0)) return m.diffuse;
    const double s = (c * p - b * q) / det, t = (a * q - b * p) / det;
    const Vec2 uv = f.uv[0] + s * (f.uv[1] - f.uv[0]) + t * (f.uv[2] - f.uv[0]);
    const Texture& tex = textures[size_t(m.diffuse_texture)];
    const Rgb mean = tex.average;
    const Rgb local = tex.filtered(uv, footprint);
    Rgb out;
    for (int ch = 0; ch < 3; ++ch)
        out[ch] = mean[ch] > 0 ? m.diffuse[ch] * local[ch] / mean[ch] : 0.0;
    return glm::min(out, Rgb(1.0) - m.specular);
}

int Scene::emitter_count() const {
    return static_cast<int>(std::count_if(
        faces.begin(), faces.end(), [&](const Face& f) { return material_of(f).is_emitter(); }));
}

int Scene::specular_face_count() const {
    return static_cast<int>(std::count_if(
        faces.begin(), faces.end(), [&](const Face& f) { return material_of(f).is_specular(); }));
}

}  // namespace vlf
