/*
 * independent — uniform, independent random samples: each sample of each pixel starts a
 * PCG32 generator at a hash of (seed, pixel, sample index), so a sample is the same
 * whatever thread, block or pass renders it.
 *
 * No parameters of its own: it takes those of every sampler, sampleCount, seed,
 * maxTolerance and minSamples (adaptive sampling; see docs/plugins.md).
 *
 *   <sampler type="independent">
 *       <integer name="sampleCount" value="64"/>
 *   </sampler>
 */
#include <nori/hash.h>
#include <nori/pcg32.h>
#include <nori/sampler.h>

namespace nori {
namespace {

class Independent : public Sampler {
public:
    explicit Independent(const PropertyList &props) { (void)props; }

    std::unique_ptr<Sampler> clone() const override { return std::make_unique<Independent>(*this); }

    float next1D() override { return m_random.nextFloat(); }

    Point2f next2D() override {
        const float x = m_random.nextFloat();
        return Point2f(x, m_random.nextFloat());
    }

    std::string toString() const override {
        return fmt::format("Independent[{}]", commonPropertiesString());
    }

protected:
    void startSample() override {
        // Both the starting state and the stream (the LCG's increment) are hashes: PCG32
        // streams that share a state are correlated (their states are affine in the
        // increment), so the state must differ between pixels too. Two samples' runs of
        // a few thousand numbers then overlap with probability about 2^-40.
        const uint64_t stream = hashValues(m_pixel.x(), m_pixel.y());
        m_random.seed(hashValues(m_seed, m_pixel.x(), m_pixel.y(), m_sampleIndex), stream);
    }

private:
    PCG32 m_random;
};

NORI_REGISTER_CLASS(Independent, "independent");

} // namespace
} // namespace nori
