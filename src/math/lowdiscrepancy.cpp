#include <nori/lowdiscrepancy.h>

#include <algorithm>
#include <array>
#include <cmath>

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

namespace {

/// The direction numbers of the second Sobol' dimension, from the primitive polynomial
/// x + 1 with m_1 = 1: m_k = 2·m_{k−1} ⊕ m_{k−1} (Joe and Kuo 2008, eq. 3), v_k = m_k/2^k.
/// The first dimension's v_k = 1/2^k is the van der Corput sequence: a bit reversal.
constexpr std::array<uint32_t, 32> secondDimensionDirections() {
    std::array<uint32_t, 32> directions{};
    uint32_t m = 1;
    for (int k = 1; k <= 32; ++k) {
        directions[k - 1] = m << (32 - k);
        m = (m << 1) ^ m;
    }
    return directions;
}

constexpr std::array<uint32_t, 32> kSecondDimension = secondDimensionDirections();

uint32_t reverseBits(uint32_t value) {
    value = (value << 16) | (value >> 16);
    value = ((value & 0x00ff00ffu) << 8) | ((value & 0xff00ff00u) >> 8);
    value = ((value & 0x0f0f0f0fu) << 4) | ((value & 0xf0f0f0f0u) >> 4);
    value = ((value & 0x33333333u) << 2) | ((value & 0xccccccccu) >> 2);
    value = ((value & 0x55555555u) << 1) | ((value & 0xaaaaaaaau) >> 1);
    return value;
}

} // namespace

uint32_t sobolSample(uint32_t index, int dimension) {
    if (dimension == 0)
        return reverseBits(index);
    uint32_t result = 0;
    for (int bit = 0; index != 0; ++bit, index >>= 1)
        if (index & 1u)
            result ^= kSecondDimension[bit];
    return result;
}

uint32_t nestedUniformScramble(uint32_t value, uint32_t seed) {
    // In bit-reversed order, each bit must depend only on the bits below it: addition
    // carries and multiplications by even constants move information upward only.
    uint32_t x = reverseBits(value);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverseBits(x);
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

float fractionToFloat(uint32_t fraction) {
    // 2^-32 · fraction rounds up to 1 for fractions within 2^-25 of it.
    return std::min(static_cast<float>(fraction) * 0x1p-32f, 0x1.fffffep-1f);
}

} // namespace nori
