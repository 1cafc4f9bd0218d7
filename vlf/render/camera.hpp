// camera.hpp — the walkthrough's pinhole camera and camera paths (VLF §6; DESIGN §7).
//
// A vlf::Camera is given in the user's scene units (as in the scene file). The pinhole
// camera converts it into the scene's normalised frame (Normalisation is a uniform scale
// plus a translation, so directions are unchanged) and generates unit primary rays.
// Image convention: pixel (x, y) covers [x, x+1] x [y, y+1], row 0 at the top; the
// camera's right is forward x up (a right-handed frame).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

class PinholeCamera {
  public:
    // Throws ParameterError for a degenerate camera (eye == look_at, up parallel to the
    // view direction, fov outside (0, 180), non-positive size).
    PinholeCamera(const Camera& camera, const Normalisation& norm, int width, int height);

    const Vec3& origin() const { return m_eye; }  // normalised coordinates
    const Vec3& forward() const { return m_forward; }
    // Unit direction through the image point (px, py), px in [0, width], py in [0, height]
    // (continuous pixel coordinates; the centre of pixel (x, y) is (x + 0.5, y + 0.5)).
    Vec3 direction(double px, double py) const;

  private:
    Vec3 m_eye, m_forward, m_right, m_up;
    double m_tan_half_y = 1.0, m_tan_half_x = 1.0;
    int m_width = 1, m_height = 1;
};

// What is wrong with a camera (non-finite values, eye == look_at, up zero or parallel to
// the view direction, fov outside (0, 180)), or nothing.
std::optional<std::string> camera_problem(const Camera& camera);
// Throws ParameterError ("<what>: <problem>") for a degenerate camera.
void validate_camera(const Camera& camera, const std::string& what);

// A keyframed camera path, JSON:
//   {"keyframes": [{"eye": [x,y,z], "look_at": [x,y,z], "up": [x,y,z], "fov_y_deg": f,
//                   "time": t}, ...], "frames": n}
// Keyframe times strictly increase; "up" defaults to [0,1,0], "fov_y_deg" to 45, "time"
// to the keyframe's index. Frames are spread evenly over [first time, last time].
struct CameraKeyframe {
    Camera camera;
    double time = 0.0;
};

struct CameraPath {
    std::vector<CameraKeyframe> keyframes;  // at least one
    int frames = 1;

    // The camera at time t (clamped to the keyframes' span): eye and look_at by a
    // Catmull-Rom spline (non-uniform times, Hermite form); up from the spherical linear
    // interpolation (slerp) of the keyframes' orientations, made orthogonal to the
    // interpolated view direction (a unit vector); fov linearly.
    Camera at(double t) const;
    // Frame k of `frames` (k = 0 .. frames-1).
    Camera frame(int k) const;
};

// Throw Error "<file>: <json.path>: <problem>" (core/json_reader.hpp); unknown keys are
// refused. `name` names the file in messages.
CameraPath camera_path_from_json(const nlohmann::json& j, const std::string& name);
CameraPath load_camera_path(const std::string& path);

}  // namespace vlf
