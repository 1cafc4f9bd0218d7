// stopwatch.hpp — wall-clock seconds for the timing buckets of reports and progress lines.
#pragma once

#include <chrono>

namespace vlf {

class Stopwatch {
  public:
    Stopwatch() : m_start(Clock::now()) {}
    // Seconds since construction or the last lap().
    double seconds() const { return std::chrono::duration<double>(Clock::now() - m_start).count(); }
    // seconds(), and start again from now.
    double lap() {
        const Clock::time_point now = Clock::now();
        const double s = std::chrono::duration<double>(now - m_start).count();
        m_start = now;
        return s;
    }

  private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point m_start;
};

}  // namespace vlf
