// What a program says of its build (nori --version): the build type, the instruction set,
// the compiler and the options that change speed, for bug reports and benchmarks.
#pragma once

#include <string>

namespace nori {

/// One line: "build type Release, AVX2 (-march=native), GCC 12.2, precompiled headers
/// on, sanitizers off".
std::string buildDescription();

} // namespace nori
