// Negative controls of the AddressSanitizer and UndefinedBehaviorSanitizer run
// (scripts/sanitize.sh): `planted_memory_errors overflow` reads one element past a heap
// array, `planted_memory_errors shift` shifts an int by its width. ctest expects each
// sanitizer's report; a build that does not report them checks nothing.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s overflow|shift\n", argv[0]);
        return 2;
    }
    // The sizes come from the command line, so that the compiler cannot see the error.
    const int count = static_cast<int>(std::strlen(argv[1]));
    if (std::strcmp(argv[1], "overflow") == 0) {
        std::vector<int> values(static_cast<size_t>(count), 1);
        const int *data = values.data();
        std::printf("past the end: %d\n", data[count]);
    } else {
        const int width = 24 + count + 3; // "shift": 32, one more than an int's last bit
        std::printf("1 << %d = %d\n", width, 1 << width);
    }
    return 0;
}
