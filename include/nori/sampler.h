// Sample generators. The render loop calls prepare() once per image block, generate()
// at the start of every pixel (seeding is per pixel, so an image does not depend on the
// thread count or block order) and advance() between the samples of a pixel.
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
    /// Called before a block is rendered (e.g. to precompute stratification).
    virtual void prepare(const ImageBlock &block) = 0;
    /// Starts the sample sequence of a pixel (absolute image coordinates).
    virtual void generate(const Point2i &pixel) = 0;
    /// Moves on to the next sample of the current pixel.
    virtual void advance() = 0;
    virtual float next1D() = 0;
    virtual Point2f next2D() = 0;

    size_t getSampleCount() const { return m_sampleCount; }
    void setSampleCount(size_t sampleCount) { m_sampleCount = sampleCount; }

    EClassType getClassType() const override { return kClassType; }

protected:
    size_t m_sampleCount = 1;
};

} // namespace nori
