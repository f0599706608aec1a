// Cameras turn a film position (in pixels) and an aperture sample into a ray.
#pragma once

#include <nori/color.h>
#include <nori/medium.h>
#include <nori/object.h>
#include <nori/ray.h>
#include <nori/rfilter.h>

namespace nori {

class Camera : public NoriObject {
public:
    static constexpr EClassType kClassType = ECamera;

    /// Which way the image's x axis runs in camera space (the two Nori course lineages
    /// differ). EPFL: Nori 2 and Mitsuba mirror x, camera-space +x is the image's left;
    /// the default. ETH: no mirror, camera-space +x is the image's right.
    enum class Convention { EPFL, ETH };

    /// Generates a world-space ray for film position `samplePosition` (pixels, from the
    /// top-left corner) and returns the importance weight of the ray. A weight of zero
    /// (a lens system blocked the ray) leaves `ray` unspecified: it must not be traced.
    virtual Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                              const Point2f &apertureSample) const = 0;

    /// sampleRay with ray differentials: the rays through the film positions one pixel
    /// to the right and one pixel down, with the same aperture sample (Igehy 1999; pbrt-v3
    /// §6.1). Any camera gets them this way; one with a cheaper closed form may override.
    virtual Color3f sampleRayDifferential(Ray3f &ray, const Point2f &samplePosition,
                                          const Point2f &apertureSample) const;

    const Vector2i &getOutputSize() const { return m_outputSize; }
    const ReconstructionFilter *getReconstructionFilter() const { return m_rfilter.get(); }
    /// The medium the camera sits in (a <medium> child), or nullptr for vacuum.
    const Medium *getMedium() const { return m_medium.get(); }

    /// Accepts one <rfilter> and one <medium>.
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Checks the image size against kMaxImageSide and kMaxImagePixels and creates the
    /// default gaussian filter (Nori's default) when none was given.
    void activate() override;

    /// The largest image: 32768 pixels on a side, 2^27 (134 million) pixels in all,
    /// which the render loop holds in about 4 GiB.
    static constexpr int kMaxImageSide = 32768;
    static constexpr int64_t kMaxImagePixels = int64_t(1) << 27;

    EClassType getClassType() const override { return kClassType; }

protected:
    /// Reads the `convention` parameter ("epfl", the default, or "eth"); `nori
    /// --camera-convention` sets it for cameras whose XML does not.
    static Convention readConvention(const PropertyList &props);
    /// The camera-space x of the film's horizontal position u in [0, 1], on the plane
    /// where the film spans x in [−1, 1]: 1 − 2u (EPFL) or 2u − 1 (ETH).
    static float filmX(float u, Convention convention) {
        return convention == Convention::EPFL ? 1.0f - 2.0f * u : 2.0f * u - 1.0f;
    }
    static const char *conventionName(Convention convention) {
        return convention == Convention::EPFL ? "epfl" : "eth";
    }

    Vector2i m_outputSize;
    std::shared_ptr<ReconstructionFilter> m_rfilter;
    std::shared_ptr<Medium> m_medium;
};

} // namespace nori
