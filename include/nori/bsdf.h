// Bidirectional scattering distribution functions. Directions are in the local shading
// frame (normal along +z) and both wi and wo point away from the surface.
#pragma once

#include <nori/color.h>
#include <nori/object.h>
#include <nori/vector.h>

namespace nori {

/// The measure a density is expressed in.
enum EMeasure { EUnknownMeasure = 0, ESolidAngle, EDiscrete };

struct BSDFQueryRecord {
    Vector3f wi;                        ///< incident direction (toward the light / camera)
    Vector3f wo;                        ///< outgoing direction, set by sample()
    float eta = 1.0f;                   ///< relative index of refraction of the sampled event
    EMeasure measure = EUnknownMeasure; ///< measure of the sampled or queried density
    Point2f uv;                         ///< surface uv, for textured parameters
    Point3f p;                          ///< world-space position, for 3D textures

    explicit BSDFQueryRecord(const Vector3f &wi) : wi(wi) {}
    BSDFQueryRecord(const Vector3f &wi, const Vector3f &wo, EMeasure measure)
        : wi(wi), wo(wo), measure(measure) {}
};

class BSDF : public NoriObject {
public:
    static constexpr EClassType kClassType = EBSDF;

    /// Samples wo given wi; returns eval·cos(theta_o)/pdf, or zero when sampling fails.
    virtual Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const = 0;
    /// The BSDF value for (wi, wo); zero for discrete lobes.
    virtual Color3f eval(const BSDFQueryRecord &bRec) const = 0;
    /// The solid-angle density of sampling wo; zero for discrete lobes.
    virtual float pdf(const BSDFQueryRecord &bRec) const = 0;
    /// Whether the BSDF is (mostly) diffuse, so that light sampling pays off.
    virtual bool isDiffuse() const { return false; }

    EClassType getClassType() const override { return kClassType; }

protected:
    /// eval·|cos θo|/pdf for the direction a sample() just chose, or 0 where the density
    /// vanishes: the weight of every BSDF that samples a mixture or a microfacet normal.
    Color3f sampleWeight(const BSDFQueryRecord &bRec) const {
        const float density = pdf(bRec);
        return density > 0.0f ? Color3f(eval(bRec) * (std::abs(bRec.wo.z()) / density))
                              : Color3f(0.0f);
    }
};

} // namespace nori
