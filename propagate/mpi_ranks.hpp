// mpi_ranks.hpp — the ranks of an MPI job (Open MPI) behind vlf::Ranks (ranks.hpp), built
// with the CMake option VLF_MPI. Only the main thread calls MPI (MPI_THREAD_FUNNELED);
// oneTBB's workers inside each rank never do. Every call is nonblocking and waited for by
// polling with a back-off, so a rank waiting in the chain does not spin on a core that
// another rank (or its own threads) could use.
//
// A failed MPI call (MPI_ERRORS_RETURN) throws vlf::Error naming this rank, the peer and the
// cycle. A rank whose peer died is usually ended by mpirun first: Open MPI's mpirun notices
// the dead process ("mpirun noticed that process rank R ... exited on signal 9"), sends
// SIGTERM to every other rank, and exits non-zero; each rank then prints one line naming
// itself and the cycle it was in before it exits, so the job never hangs and the log says
// where to resume (docs/cluster.md).
#pragma once

#include <string>
#include <vector>

#include "vlf/transport/ranks.hpp"

namespace vlf {

class MpiRanks : public Ranks {
  public:
    // True when this process was started by an MPI launcher (mpirun, srun): only then is
    // MPI initialised, so a plain `propagate` never touches it.
    static bool launched();
    MpiRanks(int* argc, char*** argv);
    ~MpiRanks() override;  // MPI_Finalize
    MpiRanks(const MpiRanks&) = delete;
    MpiRanks& operator=(const MpiRanks&) = delete;

    int rank() const override { return m_rank; }
    int size() const override { return m_size; }
    void send(const void* data, uint64_t bytes, int peer) override;
    void receive(void* data, uint64_t bytes, int peer) override;
    void broadcast(void* data, uint64_t bytes, int root) override;
    std::vector<std::string> all_gather(const std::string& mine) override;
    uint64_t bytes_sent() const override { return m_sent; }
    void set_cycle(int cycle) override;
    // Ends every rank of the job with `code` (after an error on this one).
    [[noreturn]] void abort(int code);

  private:
    void check(int rc, const char* what, int peer) const;
    int m_rank = 0, m_size = 1;
    int m_cycle = 0;
    uint64_t m_sent = 0;
};

}  // namespace vlf
