// The standard error of a region's mean in ONE render, from the render's half-buffers
// (the even and the odd samples of every pixel, two independent estimates of it).
//
// Summing the pixels' own variances (the variance layer) is not enough: a filter wider
// than a pixel splats every sample into several pixels, so neighbours are positively
// correlated, and the region's mean varies more than the sum says (about π times in
// variance for the default Gaussian, whose footprint holds π pixels' worth of samples).
// The half-buffers measure that: the difference d of a pixel's two halves has the
// pixel's noise and none of its signal, so the correlation of d between pixels at an
// offset δ, pooled over the image (ρ(δ) = Σ d_p·d_(p+δ) / Σ d_p²), is the correlation of
// their noise. The variance of a region's mean is then
//     Var = 1/N² · Σ_p∈R Var_p · Σ_δ: p+δ∈R ρ(δ),   Var_p = d_p²/4,
// the sum over offsets inside the correlation radius (which must cover the filter's
// reach: twice its radius). This is the variance of a sum of a stationary field from its
// autocorrelation (e.g. Priestley, "Spectral Analysis and Time Series", §5.3), with ρ
// pooled because one pair of pixels says little; offsets beyond the radius are left out
// because their correlation is zero for a filter and would add only noise.
#pragma once

#include "testing/agreement.h"

#include <nori/bitmap.h>
#include <nori/layeredimage.h>

#include <array>
#include <vector>

namespace nori {

/// A render's pixels, their half-buffer differences and the pooled correlations.
class HalfBufferErrors {
public:
    /// The default correlation radius: 4 pixels, twice the radius of the default
    /// Gaussian and of Mitchell–Netravali.
    static constexpr int kDefaultRadius = 4;

    /// Reads the beauty, the filter weights and the even half-buffer of `render` (the
    /// channels a render with the variance layer has, see Film::develop) and pools the
    /// correlations of offsets up to `radius` pixels. Throws a NoriException naming what
    /// is missing: no half-buffers (a render without the variance layer), a pixel with
    /// fewer than two samples.
    explicit HalfBufferErrors(const LayeredImage &render, int radius = kDefaultRadius);

    /// The mean of each channel over `region` (width 0: the whole image), with its
    /// standard error.
    std::array<RegionEstimate, 3> estimate(const ImageRegion &region) const;

    /// κ = Σ_δ ρ(δ): the variance of a large region's mean over the sum of its pixels'.
    double correlationFactor() const;

private:
    /// Where ρ(dx, dy) is kept in m_correlation.
    size_t correlationIndex(int dx, int dy) const {
        const auto side = static_cast<size_t>(2 * m_radius + 1);
        return static_cast<size_t>(dy + m_radius) * side + static_cast<size_t>(dx + m_radius);
    }

    Bitmap m_value;      ///< each pixel's mean (the beauty)
    Bitmap m_difference; ///< even half − odd half, per pixel
    int m_radius;
    std::vector<double> m_correlation; ///< ρ(δ) for |δx|, |δy| ≤ radius; ρ(0) = 1
};

/// Whether `render` has the channels HalfBufferErrors reads.
bool hasHalfBuffers(const LayeredImage &render);

/// The region as "X,Y,W,H" inside an image of `size`; throws when it does not fit.
ImageRegion parseImageRegion(const std::string &name, const std::string &text,
                             const Eigen::Vector2i &size);

} // namespace nori
