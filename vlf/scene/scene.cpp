// scene.cpp — small queries on the scene model (DESIGN §3).
#include "vlf/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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

uint64_t position_hash(const Vec3& p) {
    uint64_t h = 1469598103934665603ull;
    for (int c = 0; c < 3; ++c) {
        uint64_t bits;
        const double x = p[c] == 0.0 ? 0.0 : p[c];  // -0 == +0
        std::memcpy(&bits, &x, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

namespace {

// A triangle's weights: signed sub-triangle areas about n (x on the plane) over their sum;
// x slightly outside gives a small negative weight, which extrapolates linearly. False
// when the sum is not positive (a degenerate triangle).
bool triangle_weights(const std::vector<Vec3>& v, const Vec3& n, const Vec3& x, double w[3]) {
    const double a0 = glm::dot(glm::cross(v[1] - x, v[2] - x), n);
    const double a1 = glm::dot(glm::cross(v[2] - x, v[0] - x), n);
    const double a2 = glm::dot(glm::cross(v[0] - x, v[1] - x), n);
    const double sum = a0 + a1 + a2;
    if (!(sum > 0)) return false;
    w[0] = a0 / sum, w[1] = a1 / sum, w[2] = a2 / sum;
    return true;
}

}  // namespace

void polygon_weights(const std::vector<Vec3>& v, const Vec3& n, const Vec3& x,
                     std::vector<double>& w) {
    const size_t m = v.size();
    w.assign(m, 0.0);
    if (double t[3]; m == 3 && triangle_weights(v, n, x, t)) {
        w = {t[0], t[1], t[2]};
        return;
    }
    // Scratch on the stack for the usual few corners (this runs for every ray that meets a
    // smooth quad or polygon: the heap's malloc and free were 5 % of a light's shot
    // through a torus of smooth quads).
    constexpr size_t kSmall = 16;
    Vec3 d_small[kSmall];
    double r_small[kSmall], t_small[kSmall];
    std::vector<Vec3> d_large;
    std::vector<double> r_large, t_large;
    Vec3* d = d_small;
    double *r = r_small, *t = t_small;
    if (m > kSmall) {
        d_large.resize(m), r_large.resize(m), t_large.resize(m);
        d = d_large.data(), r = r_large.data(), t = t_large.data();
    }
    for (size_t i = 0; i < m; ++i) {
        d[i] = v[i] - x;
        r[i] = glm::length(d[i]);
    }
    const double scale = *std::max_element(r, r + m);
    for (size_t i = 0; i < m; ++i)
        if (r[i] <= 1e-12 * scale) {  // at vertex i
            w[i] = 1.0;
            return;
        }
    for (size_t i = 0; i < m; ++i) {
        // tan(alpha_i / 2) of the signed angle from d_i to d_{i+1} about n.
        const size_t j = (i + 1) % m;
        const double s = glm::dot(glm::cross(d[i], d[j]), n), c = glm::dot(d[i], d[j]);
        if (std::abs(s) <= 1e-12 * r[i] * r[j] && c < 0) {  // on edge i -> j
            w[i] = r[j] / (r[i] + r[j]);
            w[j] = r[i] / (r[i] + r[j]);
            return;
        }
        t[i] = s / (r[i] * r[j] + c);
    }
    double sum = 0.0;
    for (size_t i = 0; i < m; ++i) sum += w[i] = (t[(i + m - 1) % m] + t[i]) / r[i];
    for (double& wi : w) wi /= sum;
}

Vec3 Scene::shading_normal(const Face& f, const Vec3& x) const {
    if (f.inner && f.twin >= 0) return -shading_normal(faces[size_t(f.twin)], x);
    if (f.vertex_normals.size() != f.vertices.size()) return f.normal;
    Vec3 n(0.0);
    // A triangle (most smooth faces) without polygon_weights' vector: this runs for every
    // ray that meets a smooth mirror or glass.
    if (double t[3]; f.vertices.size() == 3 && triangle_weights(f.vertices, f.normal, x, t)) {
        for (int i = 0; i < 3; ++i) n += t[i] * f.vertex_normals[size_t(i)];
    } else {
        thread_local std::vector<double> w;
        polygon_weights(f.vertices, f.normal, x, w);
        for (size_t i = 0; i < w.size(); ++i) n += w[i] * f.vertex_normals[i];
    }
    const double len = glm::length(n);
    // A convex mix of front-side normals stays in front; guard the extrapolated rim.
    if (!(len > 0) || !(glm::dot(n, f.normal) > 1e-6 * len)) return f.normal;
    return n / len;
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
