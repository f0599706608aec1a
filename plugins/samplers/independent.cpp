/*
 * independent — uniform, independent samples from a PCG32 stream per pixel, so
 * every pixel's samples are the same whatever thread or block renders it.
 *
 * Parameters:
 *   sampleCount  integer  1  samples per pixel
 *   seed         integer  0  selects another set of random sequences
 *
 *   <sampler type="independent">
 *       <integer name="sampleCount" value="64"/>
 *   </sampler>
 */
#include <nori/pcg32.h>
#include <nori/sampler.h>

namespace nori {

class Independent : public Sampler {
public:
    explicit Independent(const PropertyList &props) {
        const int sampleCount = props.getInteger("sampleCount", 1);
        if (sampleCount <= 0)
            throw NoriException("independent: 'sampleCount' must be positive, got {}", sampleCount);
        m_sampleCount = static_cast<size_t>(sampleCount);
        m_seed = props.getInteger("seed", 0);
    }

    std::unique_ptr<Sampler> clone() const override { return std::make_unique<Independent>(*this); }

    void prepare(const ImageBlock &block) override { (void)block; }

    void generate(const Point2i &pixel) override {
        // One PCG32 stream per pixel: the stream index encodes the pixel.
        const uint64_t stream = (static_cast<uint64_t>(static_cast<uint32_t>(pixel.y())) << 32) |
                                static_cast<uint32_t>(pixel.x());
        m_random.seed(static_cast<uint64_t>(m_seed), stream);
    }

    void advance() override {}

    float next1D() override { return m_random.nextFloat(); }

    Point2f next2D() override {
        const float x = m_random.nextFloat();
        return Point2f(x, m_random.nextFloat());
    }

    std::string toString() const override {
        return fmt::format("Independent[sampleCount={}, seed={}]", m_sampleCount, m_seed);
    }

private:
    int m_seed = 0;
    PCG32 m_random;
};

NORI_REGISTER_CLASS(Independent, "independent");

} // namespace nori
