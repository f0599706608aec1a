// A progress bar on stderr with elapsed time and ETA; plain lines when stderr is not
// a terminal (CI logs, pipes).
#pragma once

#include <chrono>
#include <string>

namespace nori {

/// "850 ms", "12.3 s", "4 min 05 s", "1 h 02 min".
std::string formatDuration(double seconds);

class ProgressBar {
public:
    /// `enabled = false` prints nothing at all.
    ProgressBar(std::string label, size_t total, bool enabled);
    /// Records that `done` of `total` units are finished. Not thread-safe: call it
    /// from one thread at a time.
    void update(size_t done);
    /// Prints the final state and a line break.
    void finish();
    double elapsedSeconds() const;

private:
    void print(size_t done, bool final);

    std::string m_label;
    size_t m_total;
    bool m_enabled;
    bool m_interactive;
    int m_lastDecile = -1;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastPrint;
    size_t m_done = 0;
};

} // namespace nori
