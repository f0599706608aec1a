/*
 * sobol — Owen-scrambled Sobol' points (Burley 2020, "Practical Hash-based Owen
 * Scrambling"). Every next1D() or next2D() call of a sample is a dimension of its own,
 * drawn from the first two Sobol' dimensions, a (0, 2)-sequence, "padded" as in §4 of
 * the paper: per pixel and dimension, a hash seeds a nested uniform scramble of the
 * sample index (a shuffle) and of each coordinate. So the first 2^k samples of every
 * dimension of a pixel put one point in each elementary interval of area 2^-k, pixels
 * and dimensions are decorrelated (as pbrt-v4's ZSobol does by hashing the pixel), and
 * any sample count and any number of dimensions is well defined: there is no table to
 * run out of. Sample counts that are powers of two converge best.
 *
 * No parameters of its own: it takes those of every sampler, sampleCount, seed,
 * maxTolerance and minSamples (adaptive sampling; see docs/plugins.md).
 *
 *   <sampler type="sobol">
 *       <integer name="sampleCount" value="64"/>
 *   </sampler>
 */
#include <nori/hash.h>
#include <nori/lowdiscrepancy.h>
#include <nori/sampler.h>

namespace nori {
namespace {

class Sobol : public Sampler {
public:
    explicit Sobol(const PropertyList &props) { (void)props; }

    std::unique_ptr<Sampler> clone() const override { return std::make_unique<Sobol>(*this); }

    float next1D() override {
        const uint64_t hash = dimensionHash();
        const uint32_t index = shuffledIndex(hash);
        return scrambledCoordinate(index, 0, hash);
    }

    Point2f next2D() override {
        const uint64_t hash = dimensionHash();
        const uint32_t index = shuffledIndex(hash);
        return Point2f(scrambledCoordinate(index, 0, hash), scrambledCoordinate(index, 1, hash));
    }

    std::string toString() const override {
        return fmt::format("Sobol[{}]", commonPropertiesString());
    }

private:
    uint64_t dimensionHash() { return hashValues(m_seed, m_pixel.x(), m_pixel.y(), m_dimension++); }

    /// Burley 2020, §4: an Owen scramble of the index shuffles the points but keeps each
    /// aligned run of 2^k indices (a (0, k, 2)-net) together.
    uint32_t shuffledIndex(uint64_t dimensionHash) const {
        return nestedUniformScramble(m_sampleIndex, static_cast<uint32_t>(dimensionHash));
    }

    float scrambledCoordinate(uint32_t index, int axis, uint64_t dimensionHash) const {
        const uint32_t seed = static_cast<uint32_t>(hashValues(dimensionHash, axis) >> 32);
        return fractionToFloat(nestedUniformScramble(sobolSample(index, axis), seed));
    }
};

NORI_REGISTER_CLASS(Sobol, "sobol");

} // namespace
} // namespace nori
