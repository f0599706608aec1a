// Low-discrepancy sequences: deterministic points that cover [0, 1)^n more evenly than
// random ones (PBR 4th ed. §8.6), and the hash-based scrambling that randomises them.
// The Sobol' points and their scrambling are inline: a sampler calls them for every
// dimension of every sample.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#ifdef __GFNI__
#include <immintrin.h>
#endif

namespace nori {

/// The radical inverse of `index` in a prime `base`: its digits mirrored about the radix
/// point (van der Corput; PBR 4th ed. §8.6.1). Bases 2, 3, 5, ... make the Halton points.
double radicalInverse(int base, uint64_t index);

/// The 32 bits of `value` in reverse order. Where the CPU has GFNI, one affine transform
/// over GF(2) reverses the bits of each byte (the matrix with ones on its anti-diagonal)
/// and a byte swap does the rest: 3 instructions instead of 15, three times per 2D Sobol'
/// point. Constant evaluation (the tables below) takes the portable way.
constexpr uint32_t reverseBits(uint32_t value) {
#ifdef __GFNI__
    if (!__builtin_is_constant_evaluated()) {
        const __m128i reversedBytes = _mm_gf2p8affine_epi64_epi8(
            _mm_cvtsi32_si128(static_cast<int>(value)), _mm_set1_epi64x(0x8040201008040201LL), 0);
        return __builtin_bswap32(static_cast<uint32_t>(_mm_cvtsi128_si32(reversedBytes)));
    }
#endif
    value = (value << 16) | (value >> 16);
    value = ((value & 0x00ff00ffu) << 8) | ((value & 0xff00ff00u) >> 8);
    value = ((value & 0x0f0f0f0fu) << 4) | ((value & 0xf0f0f0f0u) >> 4);
    value = ((value & 0x33333333u) << 2) | ((value & 0xccccccccu) >> 2);
    value = ((value & 0x55555555u) << 1) | ((value & 0xaaaaaaaau) >> 1);
    return value;
}

namespace detail {

/// The second Sobol' dimension's generator matrix applied a byte at a time, bit-reversed:
/// entry [b][x] is reverseBits of the XOR of the direction numbers v_{8b+k+1} of the bits
/// k set in x. The direction numbers come from the primitive polynomial x + 1 with m_1 = 1:
/// m_k = 2·m_{k−1} ⊕ m_{k−1} (Joe and Kuo 2008, eq. 3), v_k = m_k/2^k. Four lookups
/// replace a loop over the index's 32 bits (the table is 4 KiB, in the first-level cache).
constexpr std::array<std::array<uint32_t, 256>, 4> sobolSecondDimensionBytes() {
    std::array<uint32_t, 32> directions{};
    uint32_t m = 1;
    for (int k = 1; k <= 32; ++k) {
        directions[k - 1] = reverseBits(m << (32 - k));
        m = (m << 1) ^ m;
    }
    std::array<std::array<uint32_t, 256>, 4> table{};
    for (int byte = 0; byte < 4; ++byte)
        for (uint32_t x = 0; x < 256; ++x)
            for (int bit = 0; bit < 8; ++bit)
                if (x & (1u << bit))
                    table[byte][x] ^= directions[8 * byte + bit];
    return table;
}

inline constexpr std::array<std::array<uint32_t, 256>, 4> kSobolSecondDimensionBytes =
    sobolSecondDimensionBytes();

} // namespace detail

/// Coordinate `dimension` (0 or 1) of point `index` of the Sobol' sequence, as a 32-bit
/// fixed-point fraction with its bits in reverse order (the order in which the scramble
/// below works). The first dimension's v_k = 1/2^k make it the van der Corput sequence,
/// whose reversed bits are the index itself.
inline uint32_t sobolSampleReversed(uint32_t index, int dimension) {
    if (dimension == 0)
        return index;
    const auto &bytes = detail::kSobolSecondDimensionBytes;
    return bytes[0][index & 0xffu] ^ bytes[1][(index >> 8) & 0xffu] ^
           bytes[2][(index >> 16) & 0xffu] ^ bytes[3][index >> 24];
}

/// Coordinate `dimension` (0 or 1) of point `index` of the Sobol' sequence, as a 32-bit
/// fixed-point fraction. The two dimensions form a (0, 2)-sequence: every aligned run of
/// 2^k points has one point in each elementary interval of area 2^-k (PBR 4th ed. §8.7).
inline uint32_t sobolSample(uint32_t index, int dimension) {
    return reverseBits(sobolSampleReversed(index, dimension));
}

/// Burley 2020's improved Laine–Karras hash ("Practical Hash-based Owen Scrambling", §3),
/// on bit-reversed values: each bit is flipped according to a hash of the bits below it
/// (addition carries and multiplications by even constants move information upward only).
constexpr uint32_t laineKarrasPermutation(uint32_t reversed, uint32_t seed) {
    uint32_t x = reversed + seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/// A hash-based nested uniform (Owen) scramble of a 32-bit fraction: each bit is flipped
/// according to a hash of the bits above it (Burley 2020, §3). Applied to a sample index it
/// shuffles the sequence while keeping every aligned run of 2^k indices together (§4).
constexpr uint32_t nestedUniformScramble(uint32_t value, uint32_t seed) {
    return reverseBits(laineKarrasPermutation(reverseBits(value), seed));
}

/// Element `index` of a pseudo-random permutation of {0, ..., count − 1} picked by
/// `seed`, without storing it (Kensler 2013, "Correlated Multi-Jittered Sampling", §3).
uint32_t permutationElement(uint32_t index, uint32_t count, uint32_t seed);

/// A 32-bit fixed-point fraction as a float in [0, 1) (rounded down, never to 1).
constexpr float fractionToFloat(uint32_t fraction) {
    // 2^-32 · fraction rounds up to 1 for fractions within 2^-25 of it.
    return std::min(static_cast<float>(fraction) * 0x1p-32f, 0x1.fffffep-1f);
}

} // namespace nori
