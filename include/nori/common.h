// Basic definitions shared by the whole renderer: constants, the exception type and
// small numeric helpers. Vector, colour and transform types live in their own headers.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace nori {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInvTwoPi = 0.15915494309189533577f;
constexpr float kInvFourPi = 0.07957747154594766788f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// Default start of a ray's segment (Nori's Epsilon); rays leaving a surface use
/// Intersection::spawnRay instead, which offsets the origin by a computed error bound.
constexpr float kEpsilon = 1e-4f;
/// Relative distance by which shadow rays stop short of their target.
constexpr float kShadowEpsilon = 1e-4f;

/// The one exception type of the renderer. Messages name the file, XML location,
/// plugin, parameter and value concerned.
class NoriException : public std::runtime_error {
public:
    explicit NoriException(const std::string &message) : std::runtime_error(message) {}

    template <typename... Args>
    NoriException(fmt::format_string<Args...> format, Args &&...args)
        : std::runtime_error(fmt::format(format, std::forward<Args>(args)...)) {}
};

/// A NoriException whose message already begins with "file:line:col: ", so that
/// callers which add locations (the XML parser) pass it on unchanged.
class LocatedError : public NoriException {
public:
    LocatedError(const std::string &location, const std::string &message)
        : NoriException(location + ": " + message) {}
};

inline float degToRad(float degrees) {
    return degrees * (kPi / 180.0f);
}
inline float radToDeg(float radians) {
    return radians * (180.0f / kPi);
}

/// sqrt that returns 0 for slightly negative arguments produced by round-off.
inline float safeSqrt(float x) {
    return std::sqrt(std::max(x, 0.0f));
}

} // namespace nori
