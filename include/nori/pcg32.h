// PCG32 random number generator (O'Neill 2014, "PCG: A Family of Simple Fast
// Space-Efficient Statistically Good Algorithms for Random Number Generation").
#pragma once

#include <cstdint>
#include <cstring>

namespace nori {

class PCG32 {
public:
    static constexpr uint64_t kDefaultState = 0x853c49e6748fea9bULL;
    static constexpr uint64_t kDefaultStream = 0xda3e39cb94b95bdbULL;
    static constexpr uint64_t kMultiplier = 0x5851f42d4c957f2dULL;

    PCG32() = default;
    PCG32(uint64_t initState, uint64_t initSequence) { seed(initState, initSequence); }

    /// Seeds the generator: initState picks the position, initSequence the stream.
    void seed(uint64_t initState, uint64_t initSequence = 1) {
        m_state = 0;
        m_inc = (initSequence << 1u) | 1u;
        nextUInt();
        m_state += initState;
        nextUInt();
    }

    /// A uniformly distributed 32-bit integer (XSH RR output function).
    uint32_t nextUInt() {
        uint64_t old = m_state;
        m_state = old * kMultiplier + m_inc;
        uint32_t xorShifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorShifted >> rot) | (xorShifted << ((~rot + 1u) & 31));
    }

    /// A uniform float in [0, 1): 23 random mantissa bits in [1, 2), minus one.
    float nextFloat() {
        uint32_t bits = (nextUInt() >> 9) | 0x3f800000u;
        float value;
        std::memcpy(&value, &bits, sizeof(float));
        return value - 1.0f;
    }

private:
    uint64_t m_state = kDefaultState;
    uint64_t m_inc = kDefaultStream;
};

} // namespace nori
