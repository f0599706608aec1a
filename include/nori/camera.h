// Cameras turn a film position (in pixels) and an aperture sample into a ray.
#pragma once

#include <nori/color.h>
#include <nori/object.h>
#include <nori/ray.h>
#include <nori/rfilter.h>

namespace nori {

class Camera : public NoriObject {
public:
    static constexpr EClassType kClassType = ECamera;

    /// Generates a world-space ray for film position `samplePosition` (pixels, from the
    /// top-left corner) and returns the importance weight of the ray.
    virtual Color3f sampleRay(Ray3f &ray, const Point2f &samplePosition,
                              const Point2f &apertureSample) const = 0;

    const Vector2i &getOutputSize() const { return m_outputSize; }
    const ReconstructionFilter *getReconstructionFilter() const { return m_rfilter.get(); }

    /// Accepts one <rfilter>.
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Creates the default gaussian filter (Nori's default) when none was given.
    void activate() override;

    EClassType getClassType() const override { return kClassType; }

protected:
    Vector2i m_outputSize;
    std::shared_ptr<ReconstructionFilter> m_rfilter;
};

} // namespace nori
