// checkpoint.hpp — the propagation's state on disk after every cycle, so a job killed in
// its fourth hour (a lost node, a batch system's time limit) continues from its last
// complete cycle and ends with the same bake, bit for bit, as a run never interrupted
// (issue 13; docs/cluster.md).
//
// A checkpoint directory holds
//   manifest.json         format and version, the cycle the state is after, fingerprints
//                         (SHA-256) of the scene as loaded and of every parameter that
//                         changes the bake (the parameters themselves too, to name the one
//                         that differs), and the size and SHA-256 of the state file;
//   state-<cycle>.bin     Transport::save_state (transport.hpp), in this machine's byte order.
// Written in an order that survives a kill at any instant: the state file under a
// `.partial` name, fsync, rename; then the manifest likewise (the rename is the commit);
// then the directory is synced and the previous state file removed. A reader only ever
// sees a manifest naming a complete state file.
#pragma once

#include <cstdint>
#include <string>

#include "vlf/scene/scene.hpp"
#include "vlf/transport/parameters.hpp"

namespace vlf {

class Transport;

inline constexpr const char* kCheckpointFormat = "vlf-checkpoint";
inline constexpr int kCheckpointVersion = 2;

// SHA-256 of what the transport reads of the scene: faces, charts and their texels,
// materials, lights, the normalisation. Two loads of one scene file agree.
std::string scene_fingerprint(const Scene& scene);
// The parameters that change the bake: all of them but threads and the cache budget (and
// the MPI ranks, which are no parameter: every K gives the same bake).
nlohmann::json bake_parameters(const PropagateParams& params);

// Writes the state after transport.cycles_done() cycles into `dir` (created if missing),
// atomically as above. Throws Error naming the file on any failure.
void write_checkpoint(const std::string& dir, const Scene& scene, const Transport& transport);

struct CheckpointInfo {
    std::string dir;
    int cycle = 0;           // cycles the state is after
    std::string state_file;  // full path
};

// Reads `dir`/manifest.json and checks it against this run: format, version, scene and
// parameter fingerprints (a mismatch names the first parameter that differs), the state
// file's size and checksum. Cheap against a propagation; throws Error
// "<dir>: <problem>" (one line) on any defect.
CheckpointInfo check_checkpoint(const std::string& dir, const Scene& scene,
                                const PropagateParams& params);

// Loads a checked checkpoint into a transport made from the same scene and parameters
// (still at cycle 0).
void restore_checkpoint(const CheckpointInfo& info, Transport& transport);

}  // namespace vlf
