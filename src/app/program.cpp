#include "app/program.h"
#include <nori/common.h>

#include <csignal>
#include <cstdio>
#include <new>

namespace nori {

int runProgram(const std::function<int()> &body, int errorStatus) {
    // A file size limit (ulimit -f, prlimit --fsize) then ends a write with EFBIG, which
    // writeBinaryFile reports and recovers from, instead of killing the program with
    // SIGXFSZ halfway through a file.
    std::signal(SIGXFSZ, SIG_IGN);
    try {
        return body();
    } catch (const std::bad_alloc &) {
        // No formatting here: it may need the memory that just ran out.
        std::fputs("Error: out of memory (an allocation failed); try a smaller image, scene or "
                   "sample count\n",
                   stderr);
    } catch (const std::exception &error) {
        fmt::print(stderr, "Error: {}\n", error.what());
    }
    return errorStatus;
}

} // namespace nori
