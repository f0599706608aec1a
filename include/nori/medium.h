// Participating media: what a ray meets between surfaces. A medium samples where a ray
// first interacts with it (free-flight sampling) and estimates the fraction of light
// that crosses a segment unscattered (transmittance), both through the same interface of
// extinction values and majorant segments (PBR 4th ed. ch. 11 and §14.2).
#pragma once

#include <nori/color.h>
#include <nori/object.h>
#include <nori/pcg32.h>
#include <nori/ray.h>
#include <nori/volumegrid.h>

namespace nori {

class PhaseFunction;

/// How transmittance along a shadow ray is estimated.
enum class TransmittanceEstimator {
    Delta,   ///< delta tracking: survival of tentative collisions (Woodcock et al. 1965)
    Ratio,   ///< ratio tracking: the product of null-collision ratios (Novák et al. 2014)
    RayMarch ///< ray marching: exp of the optical depth summed in steps (biased)
};

/// The outcome of free-flight sampling along a ray segment.
struct MediumSample {
    bool scattered = false; ///< a real collision inside the segment: scatter at p
    float t = 0.0f;         ///< ray parameter of the collision (or the segment's end)
    Point3f p;
    /// The throughput factor: σs·T/pdf at a collision, T/P(no collision) past the segment;
    /// its expectation over the sampling is the medium's effect on the path.
    Color3f weight = Color3f(1.0f);
};

class Medium : public NoriObject {
public:
    static constexpr EClassType kClassType = EMedium;

    /// Samples the first real collision on the ray's segment [mint, maxt] (ray.d of unit
    /// length). `rng` drives the tracking loop.
    virtual MediumSample sampleFreeFlight(const Ray3f &ray, PCG32 &rng) const = 0;

    /// An unbiased estimate (biased for ray marching) of the transmittance along the ray's
    /// segment [mint, maxt] (ray.d of unit length).
    Color3f transmittance(const Ray3f &ray, PCG32 &rng, TransmittanceEstimator estimator,
                          float stepSize) const;

    /// The extinction coefficient σt at a point (per unit length).
    virtual Color3f sigmaT(const Point3f &p) const = 0;
    /// The upper bounds of σt (over all channels) along the ray's [tMin, tMax].
    virtual MajorantIterator majorants(const Ray3f &ray, float tMin, float tMax) const = 0;

    const PhaseFunction *getPhaseFunction() const { return m_phase.get(); }

    /// Accepts one <phase>.
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Fills the side of a shape it is named for ("interior" or "exterior").
    bool attachTo(NoriObject &parent, const std::string &name) override;
    /// Creates the default isotropic phase function when none was given.
    void activate() override;

    EClassType getClassType() const override { return kClassType; }

protected:
    /// Visits the tentative collisions of the ray's segment [mint, maxt] in order: in each
    /// majorant segment, a Poisson process of rate σ̄ (exponential steps). visit(t, σ̄)
    /// returns false to stop; the result is false when a visit stopped the walk.
    template <typename Visit>
    bool forEachTentativeCollision(const Ray3f &ray, PCG32 &rng, Visit &&visit) const {
        MajorantIterator segments = majorants(ray, ray.mint, ray.maxt);
        MajorantSegment segment;
        while (segments.next(segment)) {
            if (segment.sigmaMajorant <= 0.0f)
                continue;
            for (float t = segment.tMin;;) {
                t -= std::log1p(-rng.nextFloat()) / segment.sigmaMajorant;
                if (t >= segment.tMax)
                    break;
                if (!visit(t, segment.sigmaMajorant))
                    return false;
            }
        }
        return true;
    }

    /// Reads `sigmaS` and `sigmaA`, or `sigmaT` and `albedo` (never a mix), times `scale`,
    /// into σt and the single-scattering albedo σs/σt; each colour is non-negative and
    /// finite. `plugin` names the medium in messages.
    static void readCoefficients(const PropertyList &props, const std::string &plugin,
                                 Color3f &sigmaT, Color3f &albedo);

    std::shared_ptr<PhaseFunction> m_phase;

private:
    Color3f deltaTracking(const Ray3f &ray, PCG32 &rng) const;
    Color3f ratioTracking(const Ray3f &ray, PCG32 &rng) const;
    Color3f rayMarching(const Ray3f &ray, PCG32 &rng, float stepSize) const;
};

} // namespace nori
