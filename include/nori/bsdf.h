// Bidirectional scattering distribution functions. Directions are in the local shading
// frame (normal along +z) and both wi and wo point away from the surface.
#pragma once

#include <nori/color.h>
#include <nori/object.h>
#include <nori/texture.h>
#include <nori/vector.h>

namespace nori {

/// A BSDF query. It is also the TextureQuery of its point (uv, p and the footprint), so
/// textured parameters are looked up with the record itself: m_albedo->eval(bRec).
struct BSDFQueryRecord : TextureQuery {
    Vector3f wi;                        ///< incident direction (toward the light / camera)
    Vector3f wo;                        ///< outgoing direction, set by sample()
    float eta = 1.0f;                   ///< relative index of refraction of the sampled event
    EMeasure measure = EUnknownMeasure; ///< measure of the sampled or queried density

    BSDFQueryRecord(const Vector3f &wi) : wi(wi) {} // NOLINT: implicit as in Nori 2
    BSDFQueryRecord(const Vector3f &wi, const Vector3f &wo, EMeasure measure)
        : wi(wi), wo(wo), measure(measure) {}
    /// A query at a ray hit: the texture lookups use its uv and footprint.
    BSDFQueryRecord(const Intersection &its, const Vector3f &wi) : TextureQuery(its), wi(wi) {}
    BSDFQueryRecord(const Intersection &its, const Vector3f &wi, const Vector3f &wo,
                    EMeasure measure)
        : TextureQuery(its), wi(wi), wo(wo), measure(measure) {}
};

/// One Dirac lobe of a BSDF that has nothing else (smooth glass): the direction it sends
/// wi to, the probability that sample() picks it, and the lobe's whole weight, i.e. what
/// sample() returns for it times that probability (F for glass's reflection).
struct DiscreteLobe {
    Vector3f wo;
    float eta = 1.0f; ///< relative index of refraction, as BSDFQueryRecord::eta
    float probability = 0.0f;
    Color3f weight{0.0f};
};

class BSDF : public NoriObject {
public:
    static constexpr EClassType kClassType = EBSDF;
    /// The most lobes discreteLobes() lists.
    static constexpr int kMaxDiscreteLobes = 2;

    /// Samples wo given wi; returns eval·cos(theta_o)/pdf, or zero when sampling fails.
    virtual Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const = 0;
    /// The BSDF value for (wi, wo); zero for discrete lobes.
    virtual Color3f eval(const BSDFQueryRecord &bRec) const = 0;
    /// The solid-angle density of sampling wo; zero for discrete lobes.
    virtual float pdf(const BSDFQueryRecord &bRec) const = 0;
    /// Whether the BSDF is (mostly) diffuse, so that light sampling pays off.
    virtual bool isDiffuse() const { return false; }
    /// Whether this is the `null` BSDF, no surface at all: an index-matched boundary of a
    /// medium, which volumetric path tracing crosses without a bounce.
    virtual bool isNull() const { return false; }
    /// The directional albedo for light from bRec.wi: the fraction of it scattered,
    /// ∫ f(wi, wo) |cos θo| dwo, at the textured point of bRec (the `albedo` AOV, a
    /// denoiser's guide). The default estimates it from sample() with a fixed 8 × 8 grid
    /// of points; a BSDF with a closed form (diffuse: its albedo) overrides it.
    virtual Color3f albedo(const BSDFQueryRecord &bRec) const;
    /// A BSDF made of Dirac lobes only lists them for bRec.wi in `lobes` (at most
    /// kMaxDiscreteLobes, the ones sample() can pick) and returns how many, so that a camera
    /// path can follow all of them instead of picking one (Whitted 1980; photon mapping's
    /// ray-tracing pass, Jensen 2001, ch. 9). The default, 0: the BSDF
    /// does not say, and is sampled.
    virtual int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const {
        (void)bRec;
        (void)lobes;
        return 0;
    }

    /// The textures behind the BSDF's colour and float parameters.
    const TextureParameters &textures() const { return m_textures; }

    /// Becomes the BSDF of a shape or of a tmesh copy it is nested in.
    bool attachTo(NoriObject &parent, const std::string &name) override;

    EClassType getClassType() const override { return kClassType; }

protected:
    /// Read every colour and float parameter through this: m_textures.color(props, ...).
    TextureParameters m_textures;

    /// Whether bRec queries a solid-angle density with wi and wo both above the surface:
    /// the only queries where a reflection-only BSDF is not zero.
    static bool isFrontReflection(const BSDFQueryRecord &bRec) {
        return bRec.measure == ESolidAngle && bRec.wi.z() > 0.0f && bRec.wo.z() > 0.0f;
    }

    /// eval·|cos θo|/pdf for the direction a sample() just chose, or 0 where the density
    /// vanishes: the weight of every BSDF that samples a mixture or a microfacet normal.
    Color3f sampleWeight(const BSDFQueryRecord &bRec) const {
        const float density = pdf(bRec);
        return density > 0.0f ? Color3f(eval(bRec) * (std::abs(bRec.wo.z()) / density))
                              : Color3f(0.0f);
    }
};

} // namespace nori
