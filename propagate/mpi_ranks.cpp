// mpi_ranks.cpp — vlf::Ranks over MPI (mpi_ranks.hpp).
#include "mpi_ranks.hpp"

#include <fmt/format.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

// MPI counts are int: large buffers go in pieces of at most 1 GiB.
constexpr uint64_t kPiece = uint64_t(1) << 30;

// f(offset, count) over `bytes` cut into pieces of at most kPiece (MPI counts are int); at
// least one piece, so an empty message still pairs a send with its receive.
template <class F>
void in_pieces(uint64_t bytes, F f) {
    uint64_t at = 0;
    do {
        const int n = int(std::min(kPiece, bytes - at));
        f(at, n);
        at += uint64_t(n);
    } while (at < bytes);
}

// The line a rank prints when the job ends it (SIGTERM from mpirun after another rank
// died, or a batch system's time limit): prepared outside the handler, written inside it.
char g_stop_line[256] = {};

extern "C" void on_terminate(int) {
    const ssize_t ignored = ::write(STDERR_FILENO, g_stop_line, std::strlen(g_stop_line));
    (void)ignored;
    ::_exit(3);
}

// Waits for a request without spinning: MPI_Wait polls at full speed, which on a node with
// more ranks (and threads) than cores takes the core from the rank being waited for. A
// back-off of at most 0.5 ms costs nothing against a pass.
int wait_idle(MPI_Request& request) {
    int done = 0;
    long pause_ns = 1000;
    for (;;) {
        const int rc = MPI_Test(&request, &done, MPI_STATUS_IGNORE);
        if (rc != MPI_SUCCESS || done) return rc;
        const timespec pause{0, pause_ns};
        nanosleep(&pause, nullptr);
        pause_ns = std::min(pause_ns * 2, 500000L);
    }
}

}  // namespace

bool MpiRanks::launched() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

MpiRanks::MpiRanks(int* argc, char*** argv) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    set_cycle(0);
    std::signal(SIGTERM, on_terminate);
}

MpiRanks::~MpiRanks() {
    // Rank 0 may still be writing the bake: wait for it idly, then finalise.
    MPI_Request request;
    if (MPI_Ibarrier(MPI_COMM_WORLD, &request) == MPI_SUCCESS) wait_idle(request);
    MPI_Finalize();
}

void MpiRanks::set_cycle(int cycle) {
    m_cycle = cycle;
    // Before the first cycle there is nothing to resume: the rank that failed says why.
    if (cycle == 0) {
        g_stop_line[0] = '\0';
        return;
    }
    std::snprintf(g_stop_line, sizeof(g_stop_line),
                  "propagate: rank %d of %d stopped by the job in cycle %d (another rank "
                  "failed, or the job was cancelled); resume with --resume\n",
                  m_rank, m_size, cycle);
}

void MpiRanks::check(int rc, const char* what, int peer) const {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING] = {};
    int len = 0;
    MPI_Error_string(rc, text, &len);
    throw Error(fmt::format("rank {} of {}: {} with rank {} failed in cycle {}: {}", m_rank, m_size,
                            what, peer, m_cycle, text));
}

void MpiRanks::send(const void* data, uint64_t bytes, int peer) {
    const char* p = static_cast<const char*>(data);
    in_pieces(bytes, [&](uint64_t at, int n) {
        MPI_Request request;
        check(MPI_Isend(p + at, n, MPI_BYTE, peer, 0, MPI_COMM_WORLD, &request), "sending", peer);
        check(wait_idle(request), "sending", peer);
    });
    m_sent += bytes;
}

void MpiRanks::receive(void* data, uint64_t bytes, int peer) {
    char* p = static_cast<char*>(data);
    in_pieces(bytes, [&](uint64_t at, int n) {
        MPI_Request request;
        check(MPI_Irecv(p + at, n, MPI_BYTE, peer, 0, MPI_COMM_WORLD, &request), "receiving", peer);
        check(wait_idle(request), "receiving", peer);
    });
}

void MpiRanks::broadcast(void* data, uint64_t bytes, int root) {
    char* p = static_cast<char*>(data);
    in_pieces(bytes, [&](uint64_t at, int n) {
        MPI_Request request;
        check(MPI_Ibcast(p + at, n, MPI_BYTE, root, MPI_COMM_WORLD, &request), "broadcast", root);
        check(wait_idle(request), "broadcast", root);
    });
    if (m_rank == root) m_sent += bytes * uint64_t(m_size - 1);
}

std::vector<std::string> MpiRanks::all_gather(const std::string& mine) {
    // Every rank's size, then every rank's bytes broadcast from it, in rank order.
    std::vector<uint64_t> sizes(size_t(m_size), 0);
    const uint64_t own = mine.size();
    MPI_Request request;
    check(MPI_Iallgather(&own, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD,
                         &request),
          "gathering sizes", -1);
    check(wait_idle(request), "gathering sizes", -1);
    m_sent += sizeof(own) * uint64_t(m_size - 1);
    std::vector<std::string> all(static_cast<size_t>(m_size));
    for (int q = 0; q < m_size; ++q) {
        all[q] = q == m_rank ? mine : std::string(sizes[q], '\0');
        broadcast(all[q].data(), sizes[q], q);
    }
    return all;
}

void MpiRanks::abort(int code) {
    std::fflush(stdout);
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}

}  // namespace vlf
