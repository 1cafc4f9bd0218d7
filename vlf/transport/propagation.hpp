// propagation.hpp — a whole propagation run: cycles with progress and the per-cycle
// ledger, then the report (DESIGN §5; issue "Propagation"): parameters, scene, ledger,
// per-surface radiance, timings by phase, memory by structure and peak RSS.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

struct CheckpointInfo;

struct RunOptions {
    bool progress = false;                             // progress bar on stderr
    std::function<void(const LedgerEntry&)> on_cycle;  // called after every cycle
    // Not empty: the state is written there after every cycle (checkpoint.hpp).
    std::string checkpoint_dir;
    // Not null: a checked checkpoint (check_checkpoint) to continue from; on_cycle is
    // called for its cycles first, as if they had just run.
    const CheckpointInfo* resume = nullptr;
    // Not null: the ranks sharing the run (ranks.hpp); rank 0 writes the checkpoints.
    Ranks* ranks = nullptr;
    // Set: the resampling after the last cycle (VLF §5) is left to the caller, which
    // resamples a direction at a time as it writes the bake (SpecularResampler);
    // Propagation::resample_pending says whether it is due.
    bool resample_later = false;
};

struct Propagation {
    std::unique_ptr<Transport> transport;
    double seconds_total = 0.0;
    double seconds_resample = 0.0;    // backward ray-traced resampling (VLF §5)
    bool resample_pending = false;    // RunOptions::resample_later: the caller resamples
    double seconds_checkpoint = 0.0;  // writing checkpoints (and reading the resumed one)
    int resumed_after = 0;            // cycles restored from a checkpoint (0: none)
    nlohmann::json ranks;             // with several ranks: each one's share, time, memory
};

// Runs up to params.cycles cycles, stopping early once settled(ledger, stop_unshot).
Propagation propagate(const Scene& scene, const PropagateParams& params, const RunOptions& opts);
// Less than `stop_unshot` of the emitted power (every channel) is left to shoot, or nothing
// at all is (then more cycles would only repeat zeros, whatever the stop rule).
bool settled(const LedgerEntry& e, double stop_unshot);

// Per face: {"id", "object", "material", "area", "radiance_mean", "radiance_min",
// "radiance_max"} — outgoing diffuse radiance of P^T; min/max over texels at least half
// inside the face; area in user units.
nlohmann::json surface_report(const Scene& scene, const TextureMaps& maps);

// With `surfaces`, the per-face surface_report too (a million faces make it large: the
// bake's manifest does not need it).
nlohmann::json propagation_report(const Scene& scene, const PropagateParams& params,
                                  const Propagation& run, double write_seconds,
                                  bool surfaces = true);
// Sets "write", "total" and "other" (the wall time in no phase) of a report's timings_s.
void set_write_time(nlohmann::json& timings, const Propagation& run, double write_seconds);

}  // namespace vlf
