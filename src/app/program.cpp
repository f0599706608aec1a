#include "app/program.h"
#include <nori/common.h>

#include <cstdio>
#include <new>

namespace nori {

int runProgram(const std::function<int()> &body, int errorStatus) {
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
