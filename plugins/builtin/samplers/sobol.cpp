/*
 * sobol — Owen-scrambled Sobol' points (Burley 2020, "Practical Hash-based Owen
 * Scrambling"). Every next1D() or next2D() call of a sample is a dimension of its own,
 * drawn from the first two Sobol' dimensions, a (0, 2)-sequence, "padded" as in §4 of
 * the paper: per pixel and dimension, a hash seeds a nested uniform scramble of the
 * sample index (a shuffle) and of each coordinate. So the first 2^k samples of every
 * dimension of a pixel put one point in each elementary interval of area 2^-k, pixels
 * and dimensions are decorrelated (as pbrt-v4's ZSobol does by hashing the pixel), and
 * any sample count and any number of dimensions is well defined: there is no table to
 * run out of. Sample counts that are powers of two converge best. The default sampler of
 * a scene that names none (Nori 2's is independent).
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
        const Dimension dimension = nextDimension();
        return coordinate(dimension, 0);
    }

    Point2f next2D() override {
        const Dimension dimension = nextDimension();
        return Point2f(coordinate(dimension, 0), coordinate(dimension, 1));
    }

    std::string toString() const override {
        return fmt::format("Sobol[{}]", commonPropertiesString());
    }

private:
    /// A dimension's shuffled sample index and the hash its coordinates' scrambles come
    /// from. The arithmetic is arranged to reverse bits as rarely as it can (three times
    /// for a 2D point): Owen scrambling works on bit-reversed fractions, and the first
    /// Sobol' dimension is the index reversed.
    struct Dimension {
        uint32_t index;     ///< the shuffled sample index
        uint64_t scrambles; ///< the two coordinates' scramble seeds, 32 bits each
    };

    void startSample() override {
        m_pixelHash = hashValues(m_seed, m_pixel.x(), m_pixel.y());
        m_reversedSampleIndex = reverseBits(m_sampleIndex);
    }

    /// Burley 2020, §4: an Owen scramble of the index shuffles the points but keeps each
    /// aligned run of 2^k indices (a (0, k, 2)-net) together. The dimension's hash is
    /// hashValues(seed, pixel x, pixel y, dimension), the pixel's part hashed once.
    Dimension nextDimension() {
        const uint64_t hash = hashMore(m_pixelHash, m_dimension++);
        const uint32_t index =
            reverseBits(laineKarrasPermutation(m_reversedSampleIndex, static_cast<uint32_t>(hash)));
        return {index, mixBits(hash)};
    }

    /// Coordinate `axis` of the dimension's point, Owen-scrambled with a seed of its own:
    /// a half of the dimension's hash mixed once more (the index's shuffle used the low
    /// half of the hash before mixing).
    static float coordinate(const Dimension &dimension, int axis) {
        const uint32_t seed = static_cast<uint32_t>(dimension.scrambles >> (32 * axis));
        return fractionToFloat(
            reverseBits(laineKarrasPermutation(sobolSampleReversed(dimension.index, axis), seed)));
    }

    uint64_t m_pixelHash = 0;
    uint32_t m_reversedSampleIndex = 0;
};

NORI_REGISTER_CLASS(Sobol, "sobol");

} // namespace
} // namespace nori
