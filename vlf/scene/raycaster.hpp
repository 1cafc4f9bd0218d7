// raycaster.hpp — closest-hit and occlusion queries against the scene's faces, over
// Embree 3 (DESIGN §7 "primary visibility by ray casting"; VLF §5 backward ray-traced
// re-sampling and §6.3 backwards ray tracing for specular faces).
//
// Every convex planar face is fan-triangulated into one Embree triangle geometry; a
// primitive id maps back to its face id. Faces are double-sided for queries (a hit on the
// back of a face is reported; the caller decides what a back face means). Coordinates are
// the scene's *normalised* frame (unit ball). Embree works in single precision: a hit's t
// and point are refined in double precision on the hit face's plane.
#pragma once

#include <memory>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// How far off a surface the renderers start a ray cast from it, so as not to meet it again
// (normalised units): well above Embree's single-precision error (~1e-7 at |x| ~ 1), well
// below any feature of the scenes (>= 1e-4).
inline constexpr double kSurfaceOffset = 1e-5;

struct RayHit {
    int face = -1;    // hit face id, or -1
    double t = 0;     // ray parameter: point = origin + t * dir (units of |dir|)
    Vec3 point{0.0};  // normalised coordinates, on the face's plane
};

class RayCaster {
  public:
    // Builds the acceleration structure; throws vlf::Error when Embree fails or a face
    // has non-finite vertices. The scene must outlive the caster. `without_object` >= 0:
    // that object's faces are left out (outward_casters.hpp); hits name the scene's face ids.
    explicit RayCaster(const Scene& scene, int without_object = -1);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    // Closest hit with t in [tmin, tmax] (tmin < 0 counts as 0), either side of a face;
    // on a two-sided surface (a face and its twin, one polygon in the hierarchy) the face
    // whose front the ray meets.
    // `dir` need not be unit.
    // Safe to call from many threads at once.
    bool intersect(const Vec3& origin, const Vec3& dir, double tmin, double tmax,
                   RayHit& hit) const;
    // The same, never meeting face `skip` or its twin (a ray that leaves a planar face
    // does not meet it again; in single precision a grazing one may, at t ~ 0).
    bool intersect_past(int skip, const Vec3& origin, const Vec3& dir, double tmin, double tmax,
                        RayHit& hit) const;
    // Whether any face is hit with t in [tmin, tmax]. Thread-safe.
    bool occluded(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const;

    const Scene& scene() const { return m_scene; }
    int triangles() const { return m_triangles; }

  private:
    struct Impl;
    const Scene& m_scene;
    std::unique_ptr<Impl> m_impl;
    int m_triangles = 0;
};

}  // namespace vlf
