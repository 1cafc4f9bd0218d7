// parameters.hpp — every parameter of a propagation run, with its default, in one struct
// that the CLI fills, the report and the bake manifest store, and the bake reader reads
// back (STYLE: parameters serialise both ways).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "vlf/core/json_reader.hpp"
#include "vlf/field/field_params.hpp"

namespace vlf {

struct PropagateParams {
    FieldParams field;
    double texel_size = 0.0;   // user units; 0: the scene's settings.texel_size or its default
    int texel_divisions = 32;  // that default: the scene's bounding-sphere radius / this
    // Faces share a chart's texels while their normals lie within this angle of its first
    // face's (charts.hpp; 0: a chart per face).
    double chart_angle_deg = 30.0;
    int cycles = 4;  // propagation cycles (cycle 1 carries the emission); with
                     // stop_unshot > 0, the most cycles to run
    // Stop after the cycle that leaves less than this fraction of the emitted power still
    // to shoot (unshot + deferred), per channel; 0: run all `cycles`.
    double stop_unshot = 0.0;
    std::string quality = "custom";  // the preset the parameters came from (quality.hpp)
    int threads = 0;                 // 0: all hardware threads
    bool deferred = true;            // VLF §4.5 deferred propagation
    int perturbations = 0;           // VLF §5 stratified perturbed PSFs per cycle (0: off)
    // VLF §5: "perturbing the initial few [cycles] is generally adequate"; the later
    // cycles run the true directions only.
    int perturb_cycles = 1;
    double filter_sigma = 0.0;    // VLF §5 Gaussian filter of next texture maps, texels (0: off)
    int supersample = 1;          // VLF §5 super-sampled exchange at polygon boundaries (s x s)
    bool resample = true;         // VLF §5 backward ray-traced resampling of specular L_T
    bool store_all_rays = false;  // store L_T of every fragment, not only specular ones
    uint64_t seed = 1;            // perturbation stream seed
    // MiB of per-direction geometry (PSF, beam/texel overlaps, exchange partners) kept
    // across cycles; directions beyond it are rebuilt every cycle, as in the paper.
    // 0: keep nothing (least memory). Changes speed and memory only, never the bake.
    int64_t cache_budget_mib = 3072;
    // The directions (and the first shot of lights and small lamps) are cut into this many
    // fixed chunks whose sums are added in chunk order: the bake depends on it, never on the
    // number of threads or MPI ranks; an MPI job has at most this many ranks (issue 13,
    // docs/cluster.md).
    int chunks = 16;
    // Delta lights' beams dimmer than this fraction of their light's mean irradiance land
    // coarse (light_beams.hpp "Dim beams"); 0: every beam is split to half a texel.
    double light_dim = 1e-3;
    // The lamps' direct light on curved (smooth or faceted) mirrors and glass is carried on by
    // ray tracing in
    // cycle 1 (lamp_caustics.hpp), with enough rays that the relative noise they leave in the
    // texels they light is about this (RMS, weighted by the texels' light); 0: the field
    // carries that light instead.
    double caustic_noise = 0.02;
    // The final gather (render/final_gather.hpp): the faces of charts smaller than
    // `gather_below` texels take their light from `gather` rays and as many light samples
    // per vertex, gathered from the finished field; gather = 0 leaves every face on its
    // chart's texels.
    int gather = 64;
    double gather_below = 16.0;
};

// Throws ParameterError naming the option ("--tile: ...") for any out-of-range value.
void validate(const PropagateParams& p);

nlohmann::json to_json(const PropagateParams& p);
// Reads what to_json wrote (every key required, no others); values out of range are
// refused as by validate(). Throws Error "<file>: <json.path>: <problem>".
PropagateParams propagate_params_from_json(const JsonReader& r);

}  // namespace vlf
