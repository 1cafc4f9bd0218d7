// surface_specular.hpp — the specular transfer of a smooth surface as one source per
// direction (smooth_surfaces.hpp; docs/propagation.md §13 "Smooth surfaces turn ray by ray,
// as one source").
//
// In a pass's direction d, every ray of a smooth surface turns about the shading normal at
// its point (specular_turn.hpp): at a mirror rho_s of its power is reflected, at glass R of
// it is reflected and 1 - R refracted into the twin surface. Each turned direction's power
// goes to the three PSF directions enclosing it, by barycentric weight (VLF §4.2), on the
// surface that carries it (the reflecting one, or the twin). Per target (surface,
// direction, sense) the source holds the pixels that send to it: each with its ray (whose
// power the source keeps once, however many targets the ray sends to) and the part of that
// power that goes there, the depth of its point along d, its face, and which pixels around
// it the surface covers. That turn is geometry: it is made once per
// direction as a plan (SurfacePlan) and applied to the power the rays bring each cycle.
//
// The gather (phase 2, one task per target direction) is the backward mapping of VLF §4.3:
// every ray of the target surface whose centre lies in the sending pixels' footprints is
// projected back into the source PSF; where it lands on a sending pixel on the same sheet of
// the surface (the depths agree) it takes that pixel's value (power times part), and the
// pattern is scaled so the target receives exactly its power, channel by channel (DESIGN
// §5). Targets are taken in source order, so the maps do not depend on the thread or rank
// count. The mapping is geometry too: kept per direction (SurfaceGatherPlan), it reads the
// rays' power from SurfaceArrivals (on a single rank from the first gather on: the first
// cycle's power is moved there), with the same arithmetic.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/smooth_surfaces.hpp"

namespace vlf {

// A sending pixel of a target, 28 bytes (packed: the first cycle holds one per target a ray
// sends to, tens of millions at l = 2049); the power its ray brings is kept once per ray
// (SurfaceSources::power), not per target.
#pragma pack(push, 4)
struct SurfacePixel {
    int16_t i, j;     // on the source PSF's grid
    int32_t face;     // the face its ray met
    float depth;      // z of that point in the source PSF's frame
    uint32_t around;  // bit (b + 2) * 5 + (a + 2): the surface covers pixel (i + a, j + b)
    double part;      // of its ray's power that goes to the target (Fresnel part times weight)
    uint32_t ray;     // in SurfaceSources::power (and, from the direction's first plan slot
                      // on, in SurfaceArrivals::power)
};
#pragma pack(pop)
static_assert(sizeof(SurfacePixel) == 28);

// The source PSF of a pass direction.
struct SurfaceFrame {
    std::array<float, 9> rotation;  // true or perturbed direction, row-major
    int resolution;                 // of its ray grid (N, or N * supersample)
    int direction;                  // the pass direction
};

// One target of a smooth surface's source: the light of the source's direction that goes
// to surface `group / 2` along sense * omega_direction (sense +1 where group is odd).
struct SurfaceTarget {
    uint32_t group;
    int32_t direction;
    uint32_t begin;  // its pixels in SurfaceSources::pixels, up to the next target's
    int surface() const { return int(group >> 1); }
    int sense() const { return (group & 1u) ? 1 : -1; }
};

// The smooth surfaces' sources of one pass direction.
struct SurfaceSources {
    SurfaceFrame frame;
    std::vector<SurfaceTarget> targets;
    std::vector<SurfacePixel> pixels;
    // The power its surfaces' rays bring, surface by surface, each side (facing +z first),
    // each in its rays' order: where a single rank's kept plans expect it in
    // SurfaceArrivals::power from the direction's first plan slot on.
    std::vector<Rgb> power;
    bool empty() const { return targets.empty(); }
};

// One ray of a smooth surface in a pass direction (receive_step.cpp collects them).
struct SurfaceRay {
    int face;
    int i, j;      // pixel on the pass's N x N grid
    Rgb power;     // arriving on the ray
    Vec3 point;    // on the face, scene frame
    double depth;  // z of the point in the PSF's frame
};

// The geometric part of one surface side's sources in one pass direction: per target, the
// rays that send to it and the part of each ray's light they send. Made once from the rays'
// points (all of them, lit or not) and applied every cycle to the power the rays bring: the
// geometry does not change from cycle to cycle.
struct SurfacePlan {
    struct Pixel {
        uint32_t ray;     // in the rays it was made from
        uint32_t around;  // as SurfacePixel::around
        double part;      // of the ray's light (the turn's Fresnel part times the weight)
    };
    struct Target {
        int surface, direction, sense;
        uint32_t begin, end;  // its pixels
    };
    std::vector<Target> targets;
    std::vector<Pixel> pixels;
    std::vector<std::pair<uint32_t, Rgb>> lost;  // rays' parts that no PSF can carry
    uint32_t rays = 0;                           // the rays it was made from
    bool built = false;
    bool stripped = false;  // its targets dropped: the gathers keep their own plans now
    int64_t bytes() const;
    // Drops the targets once the gathers read arrivals (the losses and the ray count stay).
    void strip() {
        std::vector<Target>().swap(targets);  // (`= {}` would keep the capacity)
        std::vector<Pixel>().swap(pixels);
        stripped = true;
    }
};

// Makes the plan of the rays `rays` (all of one surface, met by light travelling along
// `incoming`).
void make_surface_plan(const Scene& scene, const DirectionSet& dirs, const SmoothSurfaces& surfaces,
                       int surface, const Vec3& incoming, const std::vector<SurfaceRay>& rays,
                       SurfacePlan& plan);
// Appends the targets of `plan` for the power `rays` bring now (the rays it was made from),
// in the PSF of out.frame, and the rays' power to out.power; adds to `lost` the power no PSF
// can carry. Every target of the plan is appended, lit or not, so a pass's sources have the
// same shape every cycle.
void apply_surface_plan(const SurfacePlan& plan, const std::vector<SurfaceRay>& rays, Rgb& lost,
                        SurfaceSources& out);

// An arrival's power alone in half a cache line: the gathers read arrivals in no order, and
// a 24-byte record straddles two lines at a third of the places, a second fetch each.
struct alignas(32) ArrivalPower {
    Rgb rgb;
};
// Where the power of the smooth surfaces' rays arrives once the plans are kept (the true
// directions' pass of a single rank, from its second cycle on): per plan slot, its rays'
// first index in `power`. The gathers read it through their kept plans instead of
// sources.
struct SurfaceArrivals {
    std::vector<uint64_t> first;  // per SurfacePlans slot, and one past the end
    std::vector<ArrivalPower> power;
    bool ready = false;  // the gathers' plans are kept and read `power`
};
// `first` from the plans' ray counts; false (and nothing kept) where they are more than a
// 32-bit index reaches.
bool index_arrivals(const std::vector<SurfacePlan>& plans, SurfaceArrivals& arrivals);
// The first cycle's power, where the kept plans read it from then on: each source's power
// moves into `arrivals` (indexed) and is released.
void power_to_arrivals(const SmoothSurfaces& surfaces, std::vector<SurfaceSources>& sources,
                       SurfaceArrivals& arrivals);
// Adds to `lost` what of the power the plan's rays bring (`power`, in its rays' order) no PSF
// can carry.
void plan_losses(const SurfacePlan& plan, const ArrivalPower* power, Rgb& lost);

SurfaceFrame surface_frame(const Mat3& rotation, int N, int direction);

// A target ray's share of a sending pixel's value in the backward mapping.
struct GatherEntry {
    int32_t ray;     // in the target surface's rays (SurfaceRays)
    uint32_t pixel;  // in the target's pixels
    float weight;
};
// A sending pixel as the gather sees it.
struct GatherPixel {
    uint32_t arrival;  // its power: in SurfaceArrivals::power (kept plans), else in its
                       // source's SurfaceSources::power
    int32_t nearest;   // the target ray nearest its point, where no entry takes its value
    double part;
};

// The backward mappings of one direction's targets, in gather order (VLF §4.3), grouped by
// target surface and sense.
struct SurfaceGatherPlan {
    struct Group {
        int surface, sense;
        uint32_t end;  // one past its last target
    };
    std::vector<Group> groups;
    std::vector<uint32_t> pixel_begin, entry_begin;  // per target, and one past the end
    std::vector<GatherPixel> pixels;
    std::vector<GatherEntry> entries;
    void clear();
};

// The surfaces' rays per (surface, direction, sense), built the first time a gather needs
// them, and the gathers' plans per direction, kept (the geometry does not change from cycle
// to cycle).
struct SurfaceRayCache {
    std::vector<SurfaceRays> rays;  // at SmoothSurfaces::slot(surface, d, sense)
    std::vector<uint8_t> built;
    std::vector<SurfaceGatherPlan> gathers;  // per direction
    int64_t bytes() const;                   // the rays
    int64_t plan_bytes() const;              // the gathers' plans
};

// Phase 2: gathers every target of `sources` (in order) into maps.unshot_next (only the
// directions `maps` holds), adding to it. `rotations[d]` is the rotation of PSF d, `N`, `m` the
// radiance-map grid. With `arrivals` (the true directions' pass of a single rank, the sources'
// power already moved there by power_to_arrivals), the power is read from the arrivals, each
// direction's plan is kept in `cache` and reads them from then on (gather_surface_arrivals),
// and arrivals->ready is set. The sources' targets and pixels are consumed: they are laid out
// by target direction first (each source's released as it is moved) and each direction's
// share is released once its gather is done; their frames and power stay. Where no source
// brings any power, the plans are made (and kept) but not run. Returns, per held direction,
// the power single precision rounded away (as gather_specular).
std::vector<Rgb> gather_surface_sources(const Scene& scene, const DirectionSet& dirs,
                                        const std::vector<Mat3>& rotations, int N, int m,
                                        const SmoothSurfaces& surfaces,
                                        std::vector<SurfaceSources>& sources,
                                        SurfaceArrivals* arrivals, SurfaceRayCache& cache,
                                        RadianceMaps& maps);
// The same gathers by the kept plans, from arrivals.power: the same maps, bit for bit.
std::vector<Rgb> gather_surface_arrivals(const Scene& scene, const DirectionSet& dirs, int N,
                                         const SmoothSurfaces& surfaces,
                                         const SurfaceArrivals& arrivals, SurfaceRayCache& cache,
                                         RadianceMaps& maps);

}  // namespace vlf
