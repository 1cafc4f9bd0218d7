// parallel.hpp — the small parallel vocabulary of the library, over oneTBB (pbrt's
// ParallelFor). Work is split by index, and every reduction is done afterwards in index
// order, so results never depend on the number of threads or on scheduling.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <memory>

namespace vlf {

// Calls f(i) for i in [begin, end), in parallel; grain = indices per task.
template <class F>
void parallel_for(long begin, long end, F&& f, long grain = 1) {
    tbb::parallel_for(tbb::blocked_range<long>(begin, end, grain),
                      [&](const tbb::blocked_range<long>& r) {
                          for (long i = r.begin(); i != r.end(); ++i) f(i);
                      });
}

// Limits the worker threads for its lifetime (0 = leave TBB's default: all cores).
class ThreadLimit {
  public:
    explicit ThreadLimit(int threads) {
        if (threads > 0)
            m_control = std::make_unique<tbb::global_control>(
                tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    }

  private:
    std::unique_ptr<tbb::global_control> m_control;
};

}  // namespace vlf
