// ranks.hpp — the processes that share one propagation (issue 13; DESIGN §5 Parallelism):
// MPI ranks on a cluster, or this process alone. The transport uses only these few
// operations, each called by every rank in the same order, so the library builds and runs
// without MPI; the MPI implementation lives with the executable (propagate/mpi_ranks.cpp).
//
// Rank r of K owns the contiguous block of chunks [r * C / K, (r + 1) * C / K) of the C =
// PropagateParams::chunks chunks, i.e. a contiguous block of directions (so K <= C). The reductions
// of a cycle keep the single process's order exactly (transport_ranks.cpp), so every K gives the
// same bake, bit for bit.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vlf {

class Ranks {
  public:
    virtual ~Ranks() = default;
    virtual int rank() const { return 0; }
    virtual int size() const { return 1; }
    // Point to point, blocking: `bytes` bytes to / from rank `peer`.
    virtual void send(const void* data, uint64_t bytes, int peer) {}
    virtual void receive(void* data, uint64_t bytes, int peer) {}
    // `bytes` bytes from rank `root` to every rank.
    virtual void broadcast(void* data, uint64_t bytes, int root) {}
    // Every rank's `mine`, in rank order, on every rank.
    virtual std::vector<std::string> all_gather(const std::string& mine) { return {mine}; }
    // Bytes this rank has sent so far (for the report).
    virtual uint64_t bytes_sent() const { return 0; }
    // The current cycle, for the message of a rank that stops because another died.
    virtual void set_cycle(int cycle) {}
};

// One process: rank 0 of 1.
inline Ranks& single_process() {
    static Ranks one;
    return one;
}

}  // namespace vlf
