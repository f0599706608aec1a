// Pixel reconstruction filters. eval() is one-dimensional and normalised to integrate to
// 1 over [-radius, radius]; the 2D filter is the separable product eval(x)·eval(y).
#pragma once

#include <nori/object.h>
#include <nori/vector.h>

#include <vector>

namespace nori {

class ReconstructionFilter : public NoriObject {
public:
    static constexpr EClassType kClassType = EReconstructionFilter;

    float getRadius() const { return m_radius; }
    virtual float eval(float x) const = 0;

    EClassType getClassType() const override { return kClassType; }

    /// The widest support a filter may have, in pixels: far beyond any useful filter, and
    /// small enough that image borders stay small.
    static constexpr float kMaxRadius = 32.0f;

protected:
    /// Validates a radius read from XML, naming the filter in the error.
    static float checkedRadius(float radius, const char *filterName);

    float m_radius = 0.5f;
};

/// Filter importance sampling (Ernst et al. 2006, "Filter Importance Sampling"): film
/// offsets drawn in proportion to |f(x)·f(y)|, each carrying the sign of f. A pixel
/// that averages its own samples with these signs as weights estimates ∫f·L / ∫f, the
/// value splatting converges to, without taking its neighbours' samples: what adaptive
/// sampling needs, where neighbours stop at different sample counts.
class FilterSampler {
public:
    /// `filter` nullptr: the box of radius 1/2. The filter is tabulated as ImageBlock
    /// does, in steps of radius/32, so both reconstruct with the same function.
    explicit FilterSampler(const ReconstructionFilter *filter);
    /// The offset from the pixel centre for a uniform `u`, and the filter's sign there.
    Point2f sample(const Point2f &u, float &sign) const;

private:
    float sample1D(float u, float &sign) const;

    float m_radius = 0.5f;
    std::vector<float> m_values; ///< the filter in each step of [0, radius)
    std::vector<float> m_cdf;    ///< of |value| over the steps, from 0 to 1
};

} // namespace nori
