#include "vlf/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

namespace vlf {

bool Progress::stderr_is_terminal() {
    return isatty(fileno(stderr)) != 0;
}

Progress::Progress(std::string label, int64_t total, bool enabled)
    : m_label(std::move(label)),
      m_total(total > 0 ? total : 1),
      m_enabled(enabled),
      m_start(std::chrono::steady_clock::now()),
      m_last_draw(m_start) {}

Progress::~Progress() {
    finish();
}

void Progress::advance(int64_t n) {
    const int64_t done = m_done.fetch_add(n) + n;
    if (!m_enabled) return;
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock() || now - m_last_draw < std::chrono::milliseconds(100)) return;
    m_last_draw = now;
    draw(done, false);
}

void Progress::finish() {
    if (m_finished) return;
    m_finished = true;
    if (m_enabled) draw(m_done.load(), true);
}

void Progress::draw(int64_t done, bool final) {
    const double frac = std::min(1.0, double(done) / double(m_total));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    const int width = 30;
    const int filled = static_cast<int>(frac * width);
    std::string bar(static_cast<size_t>(filled), '#');
    bar.append(static_cast<size_t>(width - filled), '.');
    std::string eta = "--";
    if (final)
        eta = fmt::format("{:.1f}s", elapsed);
    else if (frac > 0.0)
        eta = fmt::format("ETA {:.1f}s", elapsed * (1.0 - frac) / frac);
    std::fprintf(stderr, "\r%-18s [%s] %5.1f%% %s   %s", m_label.c_str(), bar.c_str(), 100.0 * frac,
                 eta.c_str(), final ? "\n" : "");
    std::fflush(stderr);
}

}  // namespace vlf
