// Pixel reconstruction filters. eval() is one-dimensional and normalised to integrate to
// 1 over [-radius, radius]; the 2D filter is the separable product eval(x)·eval(y).
#pragma once

#include <nori/object.h>
#include <nori/vector.h>

#include <algorithm>
#include <array>
#include <cmath>
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

/// A filter as the film reconstructs with it: tabulated in kResolution steps of
/// radius/kResolution (the value at each step's start), zero beyond the radius.
class FilterTable {
public:
    static constexpr int kResolution = 32;

    /// `filter` nullptr: the box of radius 1/2.
    explicit FilterTable(const ReconstructionFilter *filter);
    float radius() const { return m_radius; }
    /// The weight at `distance` pixels from a pixel centre along one axis.
    float weight(float distance) const {
        const int step =
            std::min(static_cast<int>(std::abs(distance) * m_lookupFactor), kResolution);
        return m_values[static_cast<size_t>(step)];
    }
    /// ∫ weight(t) dt over [a, b] ∩ [−radius, radius], exactly: the table is a step function.
    float integral(float a, float b) const;

private:
    /// ∫ weight over [0, min(t, radius)], t ≥ 0.
    float halfIntegral(float t) const;

    float m_radius = 0.5f;
    float m_lookupFactor = 0.0f;
    std::array<float, kResolution + 1> m_values{};
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
    /// The same, drawn from the filter restricted to offsets in [lower, upper] (per axis):
    /// a pixel at the image's edge samples only positions inside the image, as splatting
    /// reconstructs it from the samples inside the image alone. Where the bounds do not
    /// cut the filter, the same offset as sample(u, sign).
    Point2f sample(const Point2f &u, float &sign, const Vector2f &lower,
                   const Vector2f &upper) const;

private:
    float sample1D(float u, float &sign) const;
    float sample1D(float u, float &sign, float lower, float upper) const;
    /// The fraction of the half filter's |f| mass in [0, t], for t in [0, radius].
    float halfCdf(float t) const;

    float m_radius = 0.5f;
    std::vector<float> m_values; ///< the filter in each step of [0, radius)
    std::vector<float> m_cdf;    ///< of |value| over the steps, from 0 to 1
};

} // namespace nori
