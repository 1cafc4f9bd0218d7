// smooth_surfaces.hpp — the smooth specular surfaces of a scene as the field's specular
// transfer sees them (docs/propagation.md §13 "Smooth surfaces as one source").
//
// A smooth mirror or glass object (Face::vertex_normals) turns each ray about its own shading
// normal, so the light one direction brings to it leaves in hundreds of directions, each
// from a small patch of the surface. Its faces are grouped into surfaces, one per object and
// side (a glass object's outer faces and its inner twins are two surfaces), and the light a
// surface receives in a direction becomes one source for the whole surface (surface_specular
// .hpp) instead of one per face: a ball of 5,120 facets smaller than a ray makes a handful of
// sources per direction, not thousands, and the light lands on whichever of its faces has a
// ray where the surface sends it (no facet needs a ray of its own in every direction).
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/coverage.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct SmoothSurfaces {
    std::vector<int> of_face;             // per face: its surface, or -1 (not smooth specular)
    std::vector<std::vector<int>> faces;  // per surface: its faces, ascending
    int directions = 0;
    // Per (surface, direction, sense): the rays of the surface's faces that show their front
    // to travel along sense * direction(d) (sense 0: +, 1: -), on the radiance-map grid.
    std::vector<uint32_t> rays;

    int size() const { return int(faces.size()); }
    bool empty() const { return faces.empty(); }
    // Where (surface, direction d, sense) is kept in per-(surface, direction, sense) arrays.
    size_t slot(int surface, int d, int sense) const {
        return (size_t(surface) * size_t(directions) + size_t(d)) * 2 + (sense > 0 ? 0 : 1);
    }
    // Where (direction d, surface, side) is kept in a pass's per-(direction, surface, side)
    // arrays (side 0: facing +z of PSF d, 1: facing -z), direction by direction.
    size_t pass_slot(int d, int surface, int side) const {
        return (size_t(d) * faces.size() + size_t(surface)) * 2 + size_t(side);
    }
    // Rays that can carry light leaving `surface` along travel direction sense * omega_d.
    uint32_t carried(int surface, int d, int sense) const { return rays[slot(surface, d, sense)]; }
};

// Groups the smooth specular faces by (object, side, material) and counts their rays per
// direction.
SmoothSurfaces find_smooth_surfaces(const Scene& scene, const DirectionSet& dirs,
                                    const Coverage& coverage);

// The rays of one surface in one direction on the radiance-map grid (N x N, tiles of m):
// where they are and where the radiance maps keep them. Built for a gather
// (surface_specular.cpp) in its own frame.
struct SurfaceRays {
    struct Ray {
        int face;      // its face
        uint32_t k;    // the face's ray k (radiance maps: maps.begin(d, face) + k)
        int16_t i, j;  // pixel on the N x N grid (its point: surface_ray_point)
    };
    std::vector<Ray> rays;                      // faces ascending, each in its rasterisation order
    int i0 = 0, j0 = 0, width = 0, height = 0;  // bounding box of the pixels
    std::vector<int32_t> head;                  // per box pixel: first ray there, or -1
    std::vector<int32_t> next;                  // per ray: next ray at the same pixel, or -1
};

// The scene-frame point where ray r (of rays made in PSF `rotation` on the N x N grid) meets
// its face: recomputed when asked for, not kept (24 bytes a ray).
inline Vec3 surface_ray_point(const Scene& scene, const Mat3& rotation, int N,
                              const SurfaceRays::Ray& r) {
    return PlaneInPsf(scene.faces[size_t(r.face)], rotation, N).point(r.i, r.j);
}

// The rays of `surface` in PSF d (its `rotation`) whose faces show their front along
// `omega` (the travel direction), on the N x N grid. `maps` stores the surface's faces (its
// layout counts their rays in every direction): a face without rays in d is not rasterised.
// `twins` (cleared for this rotation) keeps the rasters a glass surface's inner twins take.
void surface_rays(const Scene& scene, const SmoothSurfaces& surfaces, const RadianceMaps& maps,
                  int surface, int d, const Mat3& rotation, const Vec3& omega, int N, int m,
                  TwinRasters& twins, SurfaceRays& out);

}  // namespace vlf
