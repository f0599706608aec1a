// Discrete and piecewise-constant distributions, sampled by inverting their CDFs
// (PBR 4th ed. §A.4): DiscretePDF (Nori's API), Distribution1D on [0,1) and
// Distribution2D on [0,1)² (marginal over rows, conditional within a row), as an
// environment map needs.
#pragma once

#include <nori/vector.h>

#include <vector>

namespace nori {

/// A discrete distribution over indices 0..n−1 with weights given by append().
class DiscretePDF {
public:
    explicit DiscretePDF(size_t reserved = 0) {
        m_cdf.reserve(reserved + 1);
        clear();
    }

    void clear();
    void reserve(size_t count) { m_cdf.reserve(count + 1); }
    /// Adds an entry with a non-negative (unnormalised) weight.
    void append(float weight);
    /// Scales the weights to sum to 1 and returns the former sum; throws NoriException
    /// when the sum is 0 or not finite (nothing to sample).
    float normalize();

    size_t size() const { return m_cdf.size() - 1; }
    bool isNormalized() const { return m_normalized; }
    float getSum() const { return m_sum; }
    float getNormalization() const { return m_normalization; }
    /// The probability of entry i (after normalize()).
    float operator[](size_t i) const { return m_cdf[i + 1] - m_cdf[i]; }

    /// The index whose CDF interval contains u, skipping zero-probability entries.
    size_t sample(float u) const;
    size_t sample(float u, float &pdf) const;
    /// As sample(), and rescales u to a fresh uniform number in [0,1) within the chosen
    /// interval, so it can be reused for another decision.
    size_t sampleReuse(float &u) const;
    size_t sampleReuse(float &u, float &pdf) const;

private:
    std::vector<float> m_cdf; ///< m_cdf[i] = sum of the weights before entry i
    float m_sum = 0.0f;
    float m_normalization = 0.0f;
    bool m_normalized = false;
};

/// A piecewise-constant density on [0,1) with n equal cells of the given weights.
class Distribution1D {
public:
    Distribution1D() = default;
    /// Throws NoriException when the weights are empty, negative, or all zero.
    explicit Distribution1D(const std::vector<float> &weights);

    size_t size() const { return m_cells.size(); }
    /// Sum of the weights divided by the count: the integral of the unnormalised function.
    float integral() const { return m_integral; }
    /// A point in [0,1) with density pdf(x); `cell` receives the cell index.
    float sampleContinuous(float u, float &pdf, size_t &cell) const;
    /// A cell index with probability weight/sum; u is rescaled for reuse.
    size_t sampleDiscrete(float &u, float &pmf) const;
    /// The density of sampleContinuous at x (0 outside [0,1)).
    float pdf(float x) const;
    /// The probability of cell i under sampleDiscrete.
    float pmf(size_t i) const { return m_cells[i]; }

private:
    DiscretePDF m_cells;
    float m_integral = 0.0f;
};

/// A piecewise-constant density on [0,1)² given by a grid of weights (row-major,
/// `height` rows of `width` cells): a row is drawn from the marginal, then a column from
/// that row's conditional distribution.
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(const std::vector<float> &weights, size_t width, size_t height);

    /// A point (x, y) in [0,1)² with density pdf(x, y).
    Point2f sampleContinuous(const Point2f &u, float &pdf) const;
    /// The same, and the cell (column, row) it was drawn in. The point's coordinates can
    /// round onto the cell's far edge, where floor(x·width) names the next cell; callers
    /// that map the point further use the cell to stay in it.
    Point2f sampleContinuous(const Point2f &u, float &pdf, Vector2i &cell) const;
    float pdf(const Point2f &p) const;

private:
    std::vector<Distribution1D> m_conditionals; ///< one per row
    Distribution1D m_marginal;                  ///< over rows, weighted by row integrals
};

} // namespace nori
