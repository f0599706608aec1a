#include "app/progress.h"
#include <nori/common.h>

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace nori {

std::string formatDuration(double seconds) {
    if (seconds < 1.0)
        return fmt::format("{:.0f} ms", seconds * 1000.0);
    // Two decimals below 10 s: benchmarks read render times of a few seconds from this
    // line, and 0.1 s would be 1-2 % of them.
    if (seconds < 10.0)
        return fmt::format("{:.2f} s", seconds);
    if (seconds < 60.0)
        return fmt::format("{:.1f} s", seconds);
    const long total = std::lround(seconds);
    if (total < 3600)
        return fmt::format("{} min {:02d} s", total / 60, total % 60);
    return fmt::format("{} h {:02d} min", total / 3600, (total % 3600) / 60);
}

ProgressBar::ProgressBar(std::string label, size_t total, bool enabled)
    : m_label(std::move(label)), m_total(std::max<size_t>(total, 1)), m_enabled(enabled),
      m_interactive(isatty(fileno(stderr)) != 0), m_start(std::chrono::steady_clock::now()),
      m_lastPrint(m_start) {}

double ProgressBar::elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void ProgressBar::update(size_t done) {
    m_done = done;
    if (!m_enabled)
        return;
    auto now = std::chrono::steady_clock::now();
    if (m_interactive) {
        // Redraw at most ten times a second.
        if (now - m_lastPrint < std::chrono::milliseconds(100))
            return;
        m_lastPrint = now;
        print(done, false);
    } else {
        int decile = static_cast<int>(10 * done / m_total);
        if (decile > m_lastDecile && decile < 10) {
            m_lastDecile = decile;
            print(done, false);
        }
    }
}

void ProgressBar::finish() {
    if (m_enabled)
        print(m_done, true);
}

void ProgressBar::print(size_t done, bool final) {
    const double fraction = static_cast<double>(done) / static_cast<double>(m_total);
    const double elapsed = elapsedSeconds();
    std::string timing = fmt::format("{} elapsed", formatDuration(elapsed));
    if (!final && done > 0)
        timing += fmt::format(", ETA {}", formatDuration(elapsed * (1.0 / fraction - 1.0)));
    if (m_interactive) {
        constexpr int kWidth = 40;
        const int filled = static_cast<int>(fraction * kWidth);
        std::string bar(static_cast<size_t>(filled), '=');
        if (filled < kWidth)
            bar += '>' + std::string(static_cast<size_t>(kWidth - filled - 1), ' ');
        fmt::print(stderr, "\r{} [{}] {:3.0f}% ({})\033[K{}", m_label, bar, 100.0 * fraction,
                   timing, final ? "\n" : "");
    } else {
        fmt::print(stderr, "{}: {:3.0f}% ({})\n", m_label, 100.0 * fraction, timing);
    }
    std::fflush(stderr);
}

} // namespace nori
