// A negative control of the ThreadSanitizer run (scripts/sanitize.sh): the bodies of one
// parallel loop (include/nori/parallel.h, as the renderer's) add to one sum without
// synchronisation. ctest expects ThreadSanitizer's data-race report; a TSan build in which
// it does not come checks nothing.
#include <nori/parallel.h>

#include <cmath>
#include <cstdio>

int main() {
    double sum = 0.0; // deliberately unsynchronised: the race the sanitizer must see
    // Enough work per index that every thread takes part before the loop ends.
    nori::parallelFor(0, 1000000, [&](int i) { sum += std::sin(0.001 * i); });
    std::printf("sum: %g\n", sum);
    return 0;
}
