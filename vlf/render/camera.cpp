// camera.cpp — pinhole cameras and keyframed camera paths (camera.hpp).
#include "vlf/render/camera.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

#include "vlf/core/error.hpp"
#include "vlf/core/json_reader.hpp"

namespace vlf {

namespace {

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The camera's orientation: the rotation taking +z to its view direction and +y to its
// up vector made orthogonal to the view.
glm::dquat orientation(const Camera& c) {
    const Vec3 forward = glm::normalize(c.look_at - c.eye);
    const Vec3 right = glm::normalize(glm::cross(c.up, forward));
    return glm::quat_cast(Mat3(right, glm::cross(forward, right), forward));
}

// `up` made a unit vector orthogonal to the view direction `view`; `fallback` (the
// interpolated view direction) stands in for an up parallel to the view.
Vec3 up_for(const Vec3& view, const Vec3& up, const Vec3& fallback) {
    const Vec3 f = glm::normalize(view);
    Vec3 u = up - glm::dot(up, f) * f;
    if (glm::length(u) < 1e-9) u = fallback - glm::dot(fallback, f) * f;
    return glm::normalize(u);
}

}  // namespace

std::optional<std::string> camera_problem(const Camera& c) {
    if (!finite(c.eye) || !finite(c.look_at) || !finite(c.up) || !std::isfinite(c.fov_y_deg))
        return "non-finite camera value";
    const Vec3 f = c.look_at - c.eye;
    if (glm::length(f) <= 0.0) return "eye and look_at coincide";
    if (!std::isfinite(glm::length(f)) || !std::isfinite(glm::length(c.eye)) ||
        !std::isfinite(glm::length(c.up)))
        return "eye, look_at or up out of range (their lengths overflow a double)";
    if (glm::length(c.up) <= 0.0) return "up is the zero vector";
    if (glm::length(glm::cross(glm::normalize(f), glm::normalize(c.up))) < 1e-9)
        return "up is parallel to the view direction";
    if (!(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0))
        return fmt::format("fov {} outside (0, 180) degrees", c.fov_y_deg);
    return std::nullopt;
}

void validate_camera(const Camera& c, const std::string& what) {
    if (const auto problem = camera_problem(c)) throw ParameterError(what + ": " + *problem);
}

PinholeCamera::PinholeCamera(const Camera& camera, const Normalisation& norm, int width, int height)
    : m_width(width), m_height(height) {
    validate_camera(camera, camera.name.empty() ? "camera" : "camera '" + camera.name + "'");
    if (width < 1 || height < 1)
        throw ParameterError(fmt::format("image size {}x{} must be positive", width, height));
    m_eye = norm.to_normalised(camera.eye);
    m_forward = glm::normalize(camera.look_at - camera.eye);  // uniform scale: unchanged
    m_right = glm::normalize(glm::cross(m_forward, camera.up));
    m_up = glm::cross(m_right, m_forward);
    m_tan_half_y = std::tan(0.5 * camera.fov_y_deg * kPi / 180.0);
    m_tan_half_x = m_tan_half_y * double(width) / double(height);
}

Vec3 PinholeCamera::direction(double px, double py) const {
    const double u = (2.0 * px / m_width - 1.0) * m_tan_half_x;
    const double v = (1.0 - 2.0 * py / m_height) * m_tan_half_y;  // row 0 at the top
    return glm::normalize(m_forward + u * m_right + v * m_up);
}

// ---------------------------------------------------------------------------------------

Camera CameraPath::at(double t) const {
    VLF_CHECK(!keyframes.empty());
    const size_t n = keyframes.size();
    if (n == 1 || t <= keyframes.front().time) return keyframes.front().camera;
    if (t >= keyframes.back().time) return keyframes.back().camera;
    size_t k = 0;
    while (k + 2 < n && keyframes[k + 1].time <= t) ++k;
    const CameraKeyframe &a = keyframes[k], &b = keyframes[k + 1];
    const double h = b.time - a.time;
    const double s = (t - a.time) / h;
    // Catmull-Rom tangents for non-uniform times; one-sided at the ends.
    auto tangent = [&](size_t i, auto get) -> Vec3 {
        const size_t lo = i == 0 ? 0 : i - 1, hi = std::min(i + 1, n - 1);
        return (get(keyframes[hi]) - get(keyframes[lo])) /
               (keyframes[hi].time - keyframes[lo].time);
    };
    auto hermite = [&](auto get) {
        const Vec3 p0 = get(a), p1 = get(b);
        const Vec3 m0 = tangent(k, get), m1 = tangent(k + 1, get);
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * m0 + (-2 * s3 + 3 * s2) * p1 +
               (s3 - s2) * h * m1;
    };
    Camera c;
    c.name = fmt::format("path@{}", t);
    c.eye = hermite([](const CameraKeyframe& f) { return f.camera.eye; });
    c.look_at = hermite([](const CameraKeyframe& f) { return f.camera.look_at; });
    // Orientation by spherical interpolation (shortest arc, constant angular speed): a
    // linear blend of the up vectors speeds up, shrinks and can flip when they are far apart.
    const glm::dquat q = glm::slerp(orientation(a.camera), orientation(b.camera), s);
    c.up = up_for(c.look_at - c.eye, q * Vec3(0, 1, 0), q * Vec3(0, 0, 1));
    c.fov_y_deg = (1 - s) * a.camera.fov_y_deg + s * b.camera.fov_y_deg;
    return c;
}

Camera CameraPath::frame(int k) const {
    const double t0 = keyframes.front().time, t1 = keyframes.back().time;
    const double t = frames <= 1 ? t0 : t0 + (t1 - t0) * double(k) / double(frames - 1);
    Camera c = at(t);
    c.name = fmt::format("frame {}", k);
    return c;
}

namespace {

CameraKeyframe read_keyframe(const JsonReader& r, size_t index, const CameraKeyframe* previous) {
    r.only_keys({"eye", "look_at", "up", "fov_y_deg", "time"});
    CameraKeyframe f;
    f.time = double(index);
    f.camera.name = fmt::format("keyframe {}", index);
    f.camera.up = Vec3(0, 1, 0);
    f.camera.fov_y_deg = 45.0;
    f.camera.eye = r.required("eye").vec3();
    f.camera.look_at = r.required("look_at").vec3();
    if (const auto up = r.optional("up")) f.camera.up = up->vec3();
    if (const auto fov = r.optional("fov_y_deg")) f.camera.fov_y_deg = fov->number();
    const auto time = r.optional("time");
    if (time) f.time = time->number();
    if (previous && !(f.time > previous->time))
        (time ? *time : r)
            .fail(
                fmt::format("times must strictly increase ({} after {})", f.time, previous->time));
    if (const auto problem = camera_problem(f.camera)) r.fail(*problem);
    return f;
}

}  // namespace

CameraPath camera_path_from_json(const nlohmann::json& j, const std::string& name) {
    const JsonReader r(j, name);
    r.only_keys({"keyframes", "frames"});
    CameraPath p;
    p.frames = r.required("frames").integer(1, 1000000);
    const std::vector<JsonReader> keyframes = r.required("keyframes").elements(1);
    for (size_t k = 0; k < keyframes.size(); ++k)
        p.keyframes.push_back(
            read_keyframe(keyframes[k], k, p.keyframes.empty() ? nullptr : &p.keyframes.back()));
    return p;
}

CameraPath load_camera_path(const std::string& path) {
    return camera_path_from_json(read_json_file<nlohmann::json>(path), path);
}

}  // namespace vlf
