// Basic definitions shared by the whole renderer: constants, the exception type and
// small numeric helpers. Vector, colour and transform types live in their own headers.
//
// The second half is Nori 2's common.h as course code uses it (its constants, macros,
// string helpers and forward declarations, and tinyformat's tfm::format), so that a
// plugin written for Nori 2 compiles unchanged; our own code uses the first half.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <fmt/args.h>
#include <fmt/format.h>
#include <fmt/ostream.h>
#include <fmt/printf.h>

namespace nori {

constexpr float kPi = 3.14159265358979323846f;
constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInvTwoPi = 0.15915494309189533577f;
constexpr float kInvFourPi = 0.07957747154594766788f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
/// Default start of a ray's segment (Nori's Epsilon); rays leaving a surface use
/// Intersection::spawnRay instead, which offsets the origin by a computed error bound.
constexpr float kEpsilon = 1e-4f;
/// Relative distance by which shadow rays stop short of their target.
constexpr float kShadowEpsilon = 1e-4f;

namespace detail {
/// A value fmt can print: the value itself when fmt has a formatter for it, else a
/// wrapper that prints it with operator<< (as tinyformat does for every type).
template <typename T> decltype(auto) printable(T &&value) {
    if constexpr (fmt::is_formattable<std::decay_t<T>, char>::value)
        return std::forward<T>(value);
    else
        return fmt::streamed(value);
}

/// Whether a message format is fmt's ("{}", "{:.3f}", "{0}") rather than printf's.
inline bool isBraceFormat(std::string_view format) {
    for (size_t i = format.find('{'); i != std::string_view::npos && i + 1 < format.size();
         i = format.find('{', i + 1)) {
        const char next = format[i + 1];
        if (next == '}' || next == ':' || (next >= '0' && next <= '9'))
            return true;
    }
    return false;
}

/// The conversion character of each argument a printf format takes, in order ('*' widths
/// and precisions count as 'd'): "%-5s %.*f" gives {'s', 'd', 'f'}.
std::vector<char> printfConversions(std::string_view format);

/// The text of any value: fmt's formatting where it has one, else operator<<.
template <typename T> std::string textOf(const T &value) {
    // A copy, passed as an rvalue: fmt refuses views (fmt::join) passed as lvalues.
    if constexpr (fmt::is_formattable<T, char>::value && std::is_copy_constructible_v<T>)
        return fmt::format("{}", T(value));
    else if constexpr (fmt::is_formattable<T, char>::value)
        return fmt::format("{}", value);
    else
        return fmt::format("{}", fmt::streamed(value));
}

/// Adds one argument for fmt's printf: numbers and C strings as they are, unless a %s
/// takes them (fmt's printf refuses %s for a number; tinyformat prints it), and any other
/// value as its text.
template <typename T>
void addPrintfArgument(fmt::dynamic_format_arg_store<fmt::printf_context> &store, bool asText,
                       const T &value) {
    using Type = std::decay_t<T>;
    constexpr bool isCString = std::is_same_v<Type, const char *> || std::is_same_v<Type, char *>;
    if constexpr (isCString || std::is_same_v<Type, std::string> ||
                  std::is_same_v<Type, std::string_view>)
        store.push_back(std::string(value));
    else if constexpr (std::is_arithmetic_v<Type> || std::is_pointer_v<Type>) {
        if (asText)
            store.push_back(textOf(value));
        else
            store.push_back(value);
    } else
        store.push_back(textOf(value));
}

/// printf-style formatting of any arguments (tinyformat's semantics: %s prints anything).
/// A format that does not fit its arguments gives the format and the reason, never an
/// exception, since it is mostly called while building one.
template <typename... Args> std::string printfFormat(std::string_view format, const Args &...args) {
    const std::vector<char> conversions = printfConversions(format);
    fmt::dynamic_format_arg_store<fmt::printf_context> store;
    size_t index = 0;
    (addPrintfArgument(store, index < conversions.size() && conversions[index++] == 's', args),
     ...);
    try {
        return fmt::vsprintf(format, fmt::basic_format_args<fmt::printf_context>(store));
    } catch (const fmt::format_error &error) {
        return std::string(format) + " [bad format: " + error.what() + "]";
    }
}

/// Formats a message given either in fmt's syntax (ours) or in printf's (Nori 2's).
template <typename... Args> std::string formatMessage(std::string_view format, Args &&...args) {
    if (!isBraceFormat(format))
        return printfFormat(format, args...);
    try {
        return fmt::format(fmt::runtime(format), printable(std::forward<Args>(args))...);
    } catch (const fmt::format_error &error) {
        return std::string(format) + " [bad format: " + error.what() + "]";
    }
}
} // namespace detail

/// The one exception type of the renderer. Messages name the file, XML location,
/// plugin, parameter and value concerned. With arguments, the message is a format in
/// fmt's syntax ("{} of {}") or, as Nori 2's code writes it, in printf's ("%s of %d").
class NoriException : public std::runtime_error {
public:
    explicit NoriException(const std::string &message) : std::runtime_error(message) {}
    explicit NoriException(const char *message) : std::runtime_error(message) {}

    template <typename First, typename... Rest>
    NoriException(std::string_view format, First &&first, Rest &&...rest)
        : std::runtime_error(detail::formatMessage(format, std::forward<First>(first),
                                                   std::forward<Rest>(rest)...)) {}
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

// ---- Nori 2's common.h -------------------------------------------------------------

#define NORI_NAMESPACE_BEGIN namespace nori {
#define NORI_NAMESPACE_END }

// Nori 2 makes M_PI a float, so that course code like std::max(M_PI * x, 0.0f) compiles.
#undef M_PI
#define M_PI 3.14159265358979323846f

/// tinyformat's interface, as Nori 2 uses it: printf syntax, any argument type.
namespace tfm {
template <typename... Args> std::string format(const char *format, const Args &...args) {
    return nori::detail::printfFormat(format, args...);
}
template <typename... Args>
void format(std::ostream &out, const char *format, const Args &...args) {
    out << nori::detail::printfFormat(format, args...);
}
template <typename... Args> void printf(const char *format, const Args &...args) {
    std::cout << nori::detail::printfFormat(format, args...);
}
template <typename... Args> void printfln(const char *format, const Args &...args) {
    std::cout << nori::detail::printfFormat(format, args...) << '\n';
}
} // namespace tfm

namespace filesystem {
class resolver;
} // namespace filesystem

namespace nori {

constexpr float Epsilon = kEpsilon;
constexpr float INV_PI = kInvPi;
constexpr float INV_TWOPI = kInvTwoPi;
constexpr float INV_FOURPI = kInvFourPi;
constexpr float SQRT_TWO = 1.41421356237309504880f;
constexpr float INV_SQRT_TWO = 0.70710678118654752440f;

template <typename Scalar, int Dim> struct TVector;
template <typename Scalar, int Dim> struct TPoint;
using Vector3f = TVector<float, 3>;
using Point2f = TPoint<float, 2>;

// Defined in nori's own headers; libraries with classes of the same names (tinygltf's
// Camera, Mesh, Sampler, Scene) make clang-tidy suspect the wrong namespace.
// NOLINTBEGIN(bugprone-forward-declaration-namespace)
class Accel;
class BSDF;
class Bitmap;
class BlockGenerator;
class Camera;
class ImageBlock;
class Integrator;
class Emitter;
struct EmitterQueryRecord;
class Mesh;
class NoriObject;
class NoriObjectFactory;
class PhaseFunction;
class ReconstructionFilter;
class Sampler;
class Scene;
// NOLINTEND(bugprone-forward-declaration-namespace)

using std::cerr;
using std::cout;
using std::endl;

/// The measure a density is expressed in (a BSDF's or a light's sample).
enum EMeasure { EUnknownMeasure = 0, ESolidAngle, EDiscrete };

using MatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;
using MatrixXu = Eigen::Matrix<uint32_t, Eigen::Dynamic, Eigen::Dynamic>;

inline float clamp(float value, float min, float max) {
    return value < min ? min : (value > max ? max : value);
}
inline int clamp(int value, int min, int max) {
    return value < min ? min : (value > max ? max : value);
}
/// (1 − t)·v1 + t·v2 (Nori 2's argument order: the weight first).
inline float lerp(float t, float v1, float v2) {
    return (1.0f - t) * v1 + t * v2;
}
/// a mod b in [0, b) for b > 0, also for negative a.
inline int mod(int a, int b) {
    const int r = a % b;
    return r < 0 ? r + b : r;
}

/// The number of hardware threads.
int getCoreCount();
/// Every line of `text` but the first indented by `amount` spaces (for nested toString).
std::string indent(const std::string &text, int amount = 2);
/// "true"/"false" (any case); throws NoriException otherwise.
bool toBool(const std::string &text);
/// A non-negative integer; throws NoriException otherwise.
unsigned int toUInt(const std::string &text);
/// Three numbers separated by commas and/or spaces; throws NoriException otherwise.
Eigen::Vector3f toVector3f(const std::string &text);
/// "152ms", "1.2s", "3.5m", "2.1h" for a time in milliseconds; precise: more digits.
std::string timeString(double milliseconds, bool precise = false);
/// "512 B", "1.5 KiB", "3.2 MiB" for a size in bytes; precise: more digits.
std::string memString(size_t bytes, bool precise = false);

/// The unit vector at polar angle theta from +z and azimuth phi.
Vector3f sphericalDirection(float theta, float phi);
/// (theta, phi) of a unit vector, phi in [0, 2π).
Point2f sphericalCoordinates(const Vector3f &direction);
/// Nori 2's fresnel(): the unpolarised reflectance of a dielectric interface (math's
/// fresnelDielectric), cosThetaI < 0 meaning arrival from the interior.
float fresnel(float cosThetaI, float extIOR, float intIOR);
/// The resolver that turns file names in a scene into paths: while a scene file is
/// read, its folder comes first (include/filesystem/resolver.h).
filesystem::resolver *getFileResolver();

} // namespace nori

#include <nori/strutil.h>
