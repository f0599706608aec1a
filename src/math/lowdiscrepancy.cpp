#include <nori/lowdiscrepancy.h>

namespace nori {

double radicalInverse(int base, uint64_t index) {
    const double inverseBase = 1.0 / base;
    double inverseBasePower = 1.0, reversed = 0.0;
    while (index > 0) {
        const uint64_t next = index / base;
        const uint64_t digit = index - next * base;
        inverseBasePower *= inverseBase;
        reversed += static_cast<double>(digit) * inverseBasePower;
        index = next;
    }
    return reversed < 1.0 ? reversed : 0x1.fffffffffffffp-1;
}

uint32_t permutationElement(uint32_t index, uint32_t count, uint32_t seed) {
    // Every step is a bijection of the low bits under `mask`; values that land at or past
    // `count` are permuted again ("cycle walking") until they fall inside.
    uint32_t mask = count - 1;
    mask |= mask >> 1;
    mask |= mask >> 2;
    mask |= mask >> 4;
    mask |= mask >> 8;
    mask |= mask >> 16;
    uint32_t i = index;
    do {
        i ^= seed;
        i *= 0xe170893du;
        i ^= seed >> 16;
        i ^= (i & mask) >> 4;
        i ^= seed >> 8;
        i *= 0x0929eb3fu;
        i ^= seed >> 23;
        i ^= (i & mask) >> 1;
        i *= 1u | seed >> 27;
        i *= 0x6935fa69u;
        i ^= (i & mask) >> 11;
        i *= 0x74dcb303u;
        i ^= (i & mask) >> 2;
        i *= 0x9e501cc3u;
        i ^= (i & mask) >> 2;
        i *= 0xc860a3dfu;
        i &= mask;
        i ^= i >> 5;
    } while (i >= count);
    return (i + seed) % count;
}

} // namespace nori
