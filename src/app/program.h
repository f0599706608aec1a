// What every program (nori, warptest, nori-bench) does with an error: print it and exit
// with a status, never abort. Out of memory is an error like the others.
#pragma once

#include <functional>

namespace nori {

/// Runs `body` and returns its exit status; an exception is printed as "Error: ..." on
/// stderr and turns into `errorStatus` (std::bad_alloc: "out of memory"). SIGXFSZ is
/// ignored, so that exceeding a file size limit is a write error, not a kill.
int runProgram(const std::function<int()> &body, int errorStatus = 1);

} // namespace nori
