// Sample generators. What a sampler returns is a pure function of (seed, pixel, sample
// index, call number): the render loop starts sample i of pixel p with generate(p, i),
// and the integrator's next1D()/next2D() calls are its dimensions, in order. So an
// image does not depend on the thread count, the block order or the pass schedule, and
// a render can be split by sample indices across machines.
#pragma once

#include <nori/object.h>
#include <nori/vector.h>

namespace nori {

class ImageBlock;

class Sampler : public NoriObject {
public:
    static constexpr EClassType kClassType = ESampler;

    /// An independent copy for another thread, with the same parameters.
    virtual std::unique_ptr<Sampler> clone() const = 0;
    /// Called before a block is rendered (a sampler may precompute something for it).
    virtual void prepare(const ImageBlock &block) { (void)block; }
    /// Starts sample `sampleIndex` of `pixel` (absolute image coordinates), at its first
    /// dimension.
    void generate(const Point2i &pixel, uint32_t sampleIndex = 0) {
        m_pixel = pixel;
        m_sampleIndex = sampleIndex;
        m_dimension = 0;
        startSample();
    }
    /// The pixel and sample index of the current sample (an integrator that keeps
    /// statistics per pixel, like the progressive photon mapper, reads them).
    const Point2i &pixel() const { return m_pixel; }
    uint32_t sampleIndex() const { return m_sampleIndex; }
    /// Moves on to the next sample of the current pixel.
    void advance() { generate(m_pixel, m_sampleIndex + 1); }
    /// The next dimension of the current sample, in [0, 1).
    virtual float next1D() = 0;
    /// The next dimension of the current sample, a point in [0, 1)².
    virtual Point2f next2D() = 0;

    size_t getSampleCount() const { return m_sampleCount; }
    void setSampleCount(size_t sampleCount) { m_sampleCount = sampleCount; }
    uint64_t getSeed() const { return m_seed; }
    /// Selects another set of sample sequences (adaptive sampling gives its decision
    /// samples a seed of their own).
    void setSeed(uint64_t seed) { m_seed = seed; }

    /// Adaptive sampling (off when maxTolerance is 0): after minSamples and after every
    /// pass, a pixel stops when the 95% confidence interval of its mean luminance,
    /// 1.96·σ/√n, is at most maxTolerance·μ.
    float getMaxTolerance() const { return m_maxTolerance; }
    size_t getMinSamples() const { return m_minSamples; }

    /// Reads sampleCount, seed, maxTolerance and minSamples, which every sampler takes.
    void readCommonProperties(const PropertyList &props) override;
    EClassType getClassType() const override { return kClassType; }

protected:
    /// Called by generate(): m_pixel and m_sampleIndex are set, m_dimension is 0.
    virtual void startSample() {}
    /// "sampleCount=16, seed=0" (with the adaptive parameters when they are on).
    std::string commonPropertiesString() const;

    Point2i m_pixel{0, 0};
    uint32_t m_sampleIndex = 0;
    uint32_t m_dimension = 0; ///< next1D/next2D calls so far in this sample
    size_t m_sampleCount = 1;
    uint64_t m_seed = 0;
    float m_maxTolerance = 0.0f;
    size_t m_minSamples = 0;
};

} // namespace nori
