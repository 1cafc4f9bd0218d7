// light_beams.hpp — the first shot of point, spot and directional lights (light.hpp) by
// adaptive beam tracing (issue 14, docs/propagation.md §12).
//
// A delta light has no area, so it owns no rays of the field's subfields; its light enters
// the field in cycle 1 as a deposit into P^N of the surfaces it reaches, directly or through
// mirrors (the caustic), and from there on it is shot like any other diffuse light.
//
// The light's directions are cut into beams that partition them exactly:
//   point, spot   the six faces of a cube around the light, R x R pixels each; a pixel's
//                 solid angle is exact (cube_solid_angle), so the beams of a point light
//                 carry 4 pi I in all (the image-space caustics paper's light-space grid of
//                 rays, §3.1, with a pyramid instead of a sample per pixel);
//   directional   a square grid on a plane across the scene's bounding ball, facing the
//                 light; each square carries E x its area (a parallel subfield of the
//                 light's own direction, VLF §3). A source with an angular diameter (the
//                 sun) is several such subfields over its disc, E split evenly.
// A beam is traced by its centre ray and its four corner rays. While its corners meet
// another surface than its centre, or its footprint is wider than half a texel (or than
// the rim reach of texel_clip.hpp), it is split in four (its power by exact solid angle, or
// by area) down to kMaxDepth levels; so shadow edges and face rims are resolved far below
// a texel, and a lit texel's power is the exact integral of the irradiance over it to
// second order in the footprint size. A leaf beam's footprint on the face its centre meets
// is clipped against the chart's texels as the field's beams are (clip_footprint_to_grid:
// over-the-rim parts mirrored back) and rho_d of its power goes to P^N by overlap area;
// rho_s of it goes on as the beam reflected at that face (each of its rays traced from the
// light and reflected exactly, so a sub-beam of a reflected beam is still an exact part of
// the light's directions); the rest is absorbed. At glass the beam splits by Fresnel's R at
// its centre ray into a reflected and a refracted beam (Snell, per ray), attenuated inside
// by Beer-Lambert.
// Beams that leave the scene escape; beams on a back face are absorbed there. Every root
// beam's power is booked as emitted, and every watt of it ends in one of those places.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/ledger.hpp"
#include "vlf/transport/texel_clip.hpp"

namespace vlf {

// The solid angle of the rectangle [u0,u1] x [v0,v1] on the plane at distance 1 from the
// eye, seen from the eye (exact).
double cube_solid_angle(double u0, double u1, double v0, double v1);

// What a share of the lights' beams deposits, in normalised power units (ledger.hpp).
struct LightShotResult {
    explicit LightShotResult(std::vector<Rgb>& n) : next(n) {}
    std::vector<Rgb>& next;  // P^N per texel (TextureMaps order)
    Rgb emitted{0.0}, absorbed{0.0}, absorbed_back{0.0}, escaped{0.0};
    NumericalLoss lost;
    int64_t leaves = 0;  // leaf beams traced
};

class LightBeams {
  public:
    // `polygons`: every face's rim in its chart's texels within `reach` (normalised units),
    // as the transport keeps them (texel_clip.hpp faces_in_texels).
    // `dim`: beams dimmer than this fraction of their light's mean irradiance land coarse
    // (kDimFootprintTexels in light_beams.cpp; PropagateParams::light_dim).
    LightBeams(const Scene& scene, const RayCaster& caster, const TextureMaps& tex,
               const std::vector<FaceInTexels>& polygons, double reach, double dim);

    // The root beams over all the scene's lights, in a fixed order.
    int64_t roots() const { return m_first.empty() ? 0 : m_first.back(); }
    // Traces root beams [k0, k1).
    void shoot(int64_t k0, int64_t k1, LightShotResult& out) const;

    // Split levels below a root beam; a point light's leaves are then at most
    // 90 deg / (R x 2^kMaxDepth) across.
    static constexpr int kMaxDepth = 10;
    // A specular path ends after this many reflections and refractions; what is left is
    // absorbed.
    static constexpr int kMaxBounces = 16;
    // A branch of a beam split by glass is followed while its weight (the product of the
    // reflectances, transmittances and glass transmittances exp(-sigma d) on its way: the
    // part of its light's power it still carries) is at least this; the rest is booked as
    // lost.cut_beam (internal reflections of internal reflections of a ball lens, light
    // guided along absorbing glass by total internal reflection).
    static constexpr double kMinWeight = 1e-3;

  private:
    // One light, or one subfield of a directional light's disc (normalised units).
    struct Source {
        const Light* light = nullptr;
        bool parallel = false;
        Vec3 position{0.0};   // point, spot
        Vec3 direction{0.0};  // parallel: the way the light travels
        Vec3 base{0.0}, e1{0.0},
            e2{0.0};          // parallel: the root grid's plane, point = base + u e1 + v e2
        Rgb unit_power{0.0};  // point, spot: intensity x scale^2; parallel: E / subfields
        int resolution = 1;   // root beams per side (of each cube face)
        // A beam dimmer than this (power per normalised area) lands coarse.
        double dim_irradiance = 0.0;
        // Parallel: which cells of a kShadowGrid x kShadowGrid grid over the root grid's
        // [-1, 1]^2 some face's shadow (the bounding box of its vertices' projection along
        // `direction`) touches. A beam from the light over no such cell meets nothing.
        std::vector<uint8_t> shadow;
    };
    // The specular surfaces a beam has met, in order: each of its rays is traced from the
    // light through them (it must meet each one's front, else it is cut), reflected or
    // refracted exactly at each; so a quarter of a beam is still an exact part of the
    // light's directions, and a mirror path is an image source of any order.
    struct Event {
        int surface = 0;  // surface_key of the faces it met
        bool refract = false;
    };
    struct Segment {
        Event events[kMaxBounces];
        int count = 0;
        int medium = -1;      // the dielectric material it runs inside, or -1
        double weight = 1.0;  // the part of the light's power it carries (kMinWeight)
    };
    struct Rect {
        int side;  // cube face (point, spot); 0 (directional)
        double u0, u1, v0, v1;
    };
    void ray(const Source& s, const Segment& g, int side, double u, double v, Vec3& o,
             Vec3& d) const;
    void fill_shadow(Source& s) const;
    bool meets_nothing(const Source& s, const Rect& r) const;
    // A beam straight from a point or spot light (corner rays `d[1..4]` from s.position,
    // counter-clockwise; d[0] its centre) whose pyramid is disjoint from the box around
    // every face: no ray of it meets anything.
    bool misses_bounds(const Source& s, const Vec3 d[5]) const;
    void child_weights(const Source& s, const Rect& r, double w[4]) const;
    // A ray of a beam and what it met (cls: the chart of the front face it meets, -1 none,
    // -2 a back face, -3 it missed a surface of its segment's events: beyond a mirror's rim,
    // or it was totally reflected where the beam was refracted).
    struct Traced {
        Vec3 o{0.0}, d{0.0};
        RayHit hit;
        int cls = -1;
        double length = 0.0;  // from the light to o, through the segment's events
    };
    Traced cast(const Source& s, const Segment& g, int side, double u, double v) const;
    void trace(const Source& s, const Rect& r, const Segment& g, const Rgb& power, int depth,
               LightShotResult& out, const Traced* known = nullptr) const;
    bool footprint(int face, const Vec3 o[5], const Vec3 d[5], Vec3 foot[4]) const;
    double rim_share(int face, const Vec3 foot[4]) const;
    void land(const Source& s, const Rect& r, const Segment& g, int depth, int cls,
              const RayHit& hit, const Vec3& dir, const Vec3 foot[4], bool foot_ok, Rgb power,
              LightShotResult& out) const;
    void go_on(const Source& s, const Rect& r, const Segment& g, int depth, const Face& f,
               bool refract, const Rgb& power, double weight, LightShotResult& out) const;
    // Faces a beam's rays may meet at one event (m_surface): one plane (a planar chart's
    // faces), one face of a flat-shaded curved chart, or one side of a smooth object (its
    // shading normals are continuous). A beam straddling two such surfaces (the edge of a
    // box, a flat facet's edge) splits there as at any edge.
    int surface_key(const Face& f) const { return m_surface[size_t(f.id)]; }
    void deposit(const Face& f, const Vec3 foot[4], bool foot_ok, const Vec3& centre,
                 const Rgb& power, LightShotResult& out, Rgb& reflected) const;

    const Scene& m_scene;
    const RayCaster& m_caster;
    const TextureMaps& m_tex;
    const std::vector<FaceInTexels>& m_polygons;
    double m_reach;
    double m_texel = 0.0;        // the scene's texel size, normalised units
    Vec3 m_lo{0.0}, m_hi{0.0};   // the box around every face's vertices, normalised units
    std::vector<int> m_surface;  // per face, surface_key
    std::vector<Source> m_sources;
    std::vector<int64_t> m_first;  // per source, one past its last root beam (prefix sums)
};

}  // namespace vlf
