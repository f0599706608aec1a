// Low-discrepancy sequences: deterministic points that cover [0, 1)^n more evenly than
// random ones (PBR 4th ed. §8.6), and the hash-based scrambling that randomises them.
#pragma once

#include <cstdint>

namespace nori {

/// The radical inverse of `index` in a prime `base`: its digits mirrored about the radix
/// point (van der Corput; PBR 4th ed. §8.6.1). Bases 2, 3, 5, ... make the Halton points.
double radicalInverse(int base, uint64_t index);

/// Coordinate `dimension` (0 or 1) of point `index` of the Sobol' sequence, as a 32-bit
/// fixed-point fraction. The two dimensions form a (0, 2)-sequence: every aligned run of
/// 2^k points has one point in each elementary interval of area 2^-k (PBR 4th ed. §8.7).
uint32_t sobolSample(uint32_t index, int dimension);

/// A hash-based nested uniform (Owen) scramble of a 32-bit fraction: each bit is flipped
/// according to a hash of the bits above it (Burley 2020, "Practical Hash-based Owen
/// Scrambling", §3, with its improved Laine–Karras hash). Applied to a sample index it
/// shuffles the sequence while keeping every aligned run of 2^k indices together (§4).
uint32_t nestedUniformScramble(uint32_t value, uint32_t seed);

/// Element `index` of a pseudo-random permutation of {0, ..., count − 1} picked by
/// `seed`, without storing it (Kensler 2013, "Correlated Multi-Jittered Sampling", §3).
uint32_t permutationElement(uint32_t index, uint32_t count, uint32_t seed);

/// A 32-bit fixed-point fraction as a float in [0, 1) (rounded down, never to 1).
float fractionToFloat(uint32_t fraction);

} // namespace nori
