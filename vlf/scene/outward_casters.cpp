#include "vlf/scene/outward_casters.hpp"

#include <algorithm>

#include "vlf/core/parallel.hpp"

namespace vlf {

namespace {

// How far in front of a face's plane a vertex of its own object may lie and still count as
// on it (normalised units: the scene fits the unit ball, and a vertex shared by faces is
// the same double in each; planes are good to ~1e-16).
constexpr double kOnPlane = 1e-12;

bool lex_less(const Vec3& a, const Vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

}  // namespace

std::vector<uint8_t> supporting_faces(const Scene& scene, int object) {
    const SceneObject& o = scene.objects[size_t(object)];
    std::vector<Vec3> points;
    for (int f = o.first_face; f < o.first_face + o.face_count; ++f)
        for (const Vec3& v : scene.faces[size_t(f)].vertices) points.push_back(v);
    std::sort(points.begin(), points.end(), lex_less);
    points.erase(std::unique(points.begin(), points.end()), points.end());
    std::vector<uint8_t> supports(size_t(o.face_count), 0);
    parallel_for(0, o.face_count, [&](long k) {
        const Face& f = scene.faces[size_t(o.first_face + k)];
        for (const Vec3& v : points)
            if (glm::dot(f.normal, v) - f.plane_offset > kOnPlane) return;
        supports[size_t(k)] = 1;
    });
    return supports;
}

OutwardCasters::OutwardCasters(const Scene& scene, const RayCaster& all,
                               const std::function<bool(int)>& wanted)
    : m_scene(scene),
      m_all(all),
      m_supports(scene.faces.size(), 0),
      m_without(scene.objects.size(), nullptr) {
    const size_t F = scene.faces.size();
    for (size_t k = 0; k < scene.objects.size(); ++k) {
        const SceneObject& o = scene.objects[k];
        const size_t n = size_t(o.face_count);
        if (n == 0 || 4 * n < F || n > kMaxFaces || !wanted(int(k))) continue;
        const std::vector<uint8_t> s = supporting_faces(scene, int(k));
        if (std::none_of(s.begin(), s.end(), [](uint8_t b) { return b != 0; })) continue;
        std::copy(s.begin(), s.end(), m_supports.begin() + o.first_face);
        m_owned.push_back(std::make_unique<RayCaster>(scene, int(k)));
        m_without[k] = m_owned.back().get();
    }
}

const RayCaster& OutwardCasters::leaving(int from, const Vec3& w) const {
    const Face& f = m_scene.faces[size_t(from)];
    const RayCaster* without = m_without[size_t(f.object)];
    if (without == nullptr) return m_all;
    const double s = glm::dot(f.normal, w);
    // The ray goes into the front of `from` (s > 0) or of its twin, whose front is from's
    // back (s < 0).
    const int front = s > 0.0 ? from : (s < 0.0 ? f.twin : -1);
    return front >= 0 && m_supports[size_t(front)] ? *without : m_all;
}

}  // namespace vlf
