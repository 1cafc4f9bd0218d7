// outward_casters.hpp — casts that leave a convex object skip its faces.
//
// A ray that leaves a point of face f into the open half-space in front of f's plane never
// meets anything that lies in the closed half-space behind it. When the whole of f's object
// lies there (f "supports" its object, as every outer face of a convex ball or box does),
// the closest hit of such a ray is the same in a hierarchy built without the object: a
// glass or mirror ball's outward casts (its reflections, and the light leaving the glass)
// then search the room alone, not the ball's thousands of triangles.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

class OutwardCasters {
  public:
    // Objects that `wanted` accepts, with at least a quarter of the scene's faces and at most
    // kMaxFaces (the test is faces x vertices), get a caster without their faces; the scene
    // and `all` (the scene's own caster) must outlive this.
    OutwardCasters(const Scene& scene, const RayCaster& all,
                   const std::function<bool(int object)>& wanted);
    // The caster for a ray that leaves face `from` along w (a point of the face): one
    // without from's object when the ray goes into the front of a face (from, or its twin
    // when w points behind from) that supports the object; else the scene's.
    const RayCaster& leaving(int from, const Vec3& w) const;
    // How many objects have their own caster.
    int objects() const { return int(m_owned.size()); }

    static constexpr size_t kMaxFaces = 20000;

  private:
    const Scene& m_scene;
    const RayCaster& m_all;
    std::vector<uint8_t> m_supports;          // per face: its object lies behind its plane
    std::vector<const RayCaster*> m_without;  // per object: a caster without it, or null
    std::vector<std::unique_ptr<RayCaster>> m_owned;
};

// Per face of object `object`: whether all the object's vertices lie on or behind the face's
// plane (within rounding of the stored vertices).
std::vector<uint8_t> supporting_faces(const Scene& scene, int object);

}  // namespace vlf
