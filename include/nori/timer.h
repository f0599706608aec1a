// A stopwatch, as Nori 2's timer.h has it: elapsed times in milliseconds.
#pragma once

#include <nori/common.h>

#include <chrono>

namespace nori {

class Timer {
public:
    Timer() { reset(); }
    void reset() { m_start = std::chrono::steady_clock::now(); }
    /// Milliseconds since construction or the last reset().
    double elapsed() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start)
            .count();
    }
    /// elapsed() as "1.2s" (timeString).
    std::string elapsedString(bool precise = false) const { return timeString(elapsed(), precise); }
    /// elapsed(), then reset().
    double lap() {
        const double time = elapsed();
        reset();
        return time;
    }

private:
    std::chrono::steady_clock::time_point m_start;
};

} // namespace nori
