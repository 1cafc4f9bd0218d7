// lamp_caustics.hpp — the direct light of the area lamps on curved mirrors and glass (smooth,
// or faceted over more than one plane), carried on by ray tracing instead of the field
// (docs/propagation.md §14).
//
// A curved mirror or glass object is a lens: the light of a lamp it turns lands in a
// caustic whose width is set by the lamp's size and the object's curvature, often far
// below the field's direction spacing. The field (VLF §4.2) turns each of its directions'
// light into the three directions around the turned one, so the caustic comes out blurred
// across a direction's footprint: under the Cornell box's glass ball, the lamp's caustic
// peak came out 2-3x too low. In cycle 1, the only light that reaches a smooth surface is
// the emitters' own (everything else is still on its way), so the field hands exactly that
// power over: the rays of cycle 1 that arrive on such a face (caustic_faces) deposit nothing
// there and their power is summed (per channel). This shot carries it on instead, with exact
// turns:
//
//   for each (lamp, object) pair, K rays from points on the lamp (uniform by area)
//   in directions uniform over the cone of the object's bounding ball, each carrying
//   L_e A cos(theta) Omega_cone / K: a Hammersley estimate of the lamp's radiance integrated
//   over the object, kept only where the ray's first hit is that object's front;
//   at a mirror rho_s goes on reflected (the rest is absorbed), at glass the ray splits by
//   Fresnel's R into a reflected and a refracted ray (both followed, Beer-Lambert inside),
//   and at a diffuse surface rho_d of it goes to the texel under the hit (P^N), the rest
//   absorbed; rays that leave escape, rays on a back face are absorbed there.
//
// The shot's rays estimate the same power that the field handed over (to the field's
// discretisation and the estimate's sampling: the ratio is reported), and every ray is
// scaled by handed / estimated per channel, so the ledger closes exactly. From cycle 2 on,
// the light the shot put on the surfaces propagates through the field as usual, and the
// smooth surfaces take their light from the field again.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/ledger.hpp"
#include "vlf/transport/small_emitters.hpp"
#include "vlf/transport/smooth_surfaces.hpp"

namespace vlf {

// Per face, 1 where the lamps' light is handed to the shot: the faces of smooth mirrors and
// glass (smooth_surfaces.hpp), and the specular faces of a flat-shaded object whose specular
// faces lie in more than one plane (a faceted ring or ball: a lens of facets, whose caustic
// the field blurs as it does a smooth one's). A mirror of one plane stays the field's: its
// image sources are the field's own transport (VLF §4.2-4.3).
std::vector<uint8_t> caustic_faces(const Scene& scene, const SmoothSurfaces& surfaces);

class LampCaustics {
  public:
    // `caustic`: caustic_faces(). `skip`: emitting charts that do not send through the field
    // (small_emitters.hpp).
    LampCaustics(const Scene& scene, const RayCaster& caster, const TextureMaps& tex,
                 const SmoothSurfaces& surfaces, const std::vector<uint8_t>& caustic,
                 const std::vector<int>& skip);

    // The (lamp, object) pairs; none when no lamp sends through the field or no face hands
    // its light over. A shot of K rays per pair has pairs() x K rays, pair by pair.
    size_t pairs() const { return m_pairs.size(); }
    // How many rays each pair needs for the shot to leave about `noise` relative noise in
    // the texels it lights, `tex.next` holding the field's cycle-1 deposits: a pilot of
    // 2^16 rays per pair shows where its light lands and how densely. A texel that n pilot
    // rays bring E of its T (the field's deposit there plus E) would hold E / sqrt(n) of
    // noise (independent rays; the Hammersley set does better); the light-weighted mean of
    // (E / T)^2 / n over the pilot's texels, over noise^2, is the factor on the pilot's
    // count (at least 2^18, at most 2^24 rays per pair; with many pairs, at most 2^20 pilot
    // rays and 2^25 shot rays in all, and at least 2^12 per pair). The pilot runs in fixed
    // chunks added in order: the same count on every rank and thread count.
    uint64_t rays_for(double noise) const;
    // The power rays [k0, k1) of a K-ray shot bring to their objects (unscaled): the
    // estimate.
    Rgb estimate(uint64_t K, uint64_t k0, uint64_t k1) const;
    // Traces rays [k0, k1) of a K-ray shot, each scaled per channel by `scale` (handed /
    // estimated).
    void shoot(uint64_t K, uint64_t k0, uint64_t k1, const Rgb& scale, ShotResult& out) const;

    // A branch split by glass is followed while it carries at least this part of its
    // ray's power; the rest is booked as lost.cut_beam (as light_beams.hpp does).
    static constexpr double kMinWeight = 1e-3;
    // A path ends after this many reflections and refractions; what is left is absorbed.
    static constexpr int kMaxBounces = 16;

  private:
    struct Pair {
        int chart;    // the lamp
        int object;   // the smooth object
        Vec3 centre;  // its bounding ball
        double radius;
    };
    // Ray k's start, direction and power (unscaled); false when it carries nothing (its
    // direction below the lamp's plane, or its first hit not on the pair's object's front).
    bool first_ray(uint64_t K, uint64_t k, Vec3& from, Vec3& dir, Rgb& power, RayHit& hit) const;

    const Scene& m_scene;
    const RayCaster& m_caster;
    const TextureMaps& m_tex;
    const SmoothSurfaces& m_surfaces;
    const std::vector<uint8_t>& m_caustic;
    std::vector<Pair> m_pairs;
};

}  // namespace vlf
