// progress.hpp — a progress bar with ETA on stderr for long passes. Silent when stderr is
// not a terminal or when the user asked for --quiet; safe to advance from many threads.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace vlf {

class Progress {
  public:
    Progress(std::string label, int64_t total, bool enabled);
    ~Progress();
    void advance(int64_t n = 1);
    void finish();
    // True when stderr is a terminal (the default for `enabled`).
    static bool stderr_is_terminal();

  private:
    void draw(int64_t done, bool final);
    std::string m_label;
    int64_t m_total;
    bool m_enabled;
    bool m_finished = false;
    std::atomic<int64_t> m_done{0};
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start, m_last_draw;
};

}  // namespace vlf
