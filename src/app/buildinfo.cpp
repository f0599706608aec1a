#include "app/buildinfo.h"

#include <fmt/format.h>

// NORI_BUILD_TYPE, NORI_BUILD_NATIVE, NORI_BUILD_PCH and NORI_BUILD_SANITIZE are set on this
// file alone (src/CMakeLists.txt), so changing them recompiles nothing else.

namespace nori {

std::string buildDescription() {
    // The instruction set the compiler targeted, from its predefined macros.
#if defined(__AVX512F__)
    const char *isa = "AVX-512";
#elif defined(__AVX2__)
    const char *isa = "AVX2";
#elif defined(__AVX__)
    const char *isa = "AVX";
#elif defined(__SSE4_2__)
    const char *isa = "SSE4.2";
#else
    const char *isa = "SSE2";
#endif
#if defined(__clang__)
    const std::string compiler = fmt::format("clang {}.{}", __clang_major__, __clang_minor__);
#elif defined(__GNUC__)
    const std::string compiler = fmt::format("GCC {}.{}", __GNUC__, __GNUC_MINOR__);
#else
    const std::string compiler = "an unknown compiler";
#endif
    return fmt::format("build type {}, {} ({}), {}, precompiled headers {}, sanitizers {}",
                       NORI_BUILD_TYPE, isa,
                       NORI_BUILD_NATIVE ? "-march=native" : "portable x86-64", compiler,
                       NORI_BUILD_PCH ? "on" : "off", NORI_BUILD_SANITIZE);
}

} // namespace nori
