// Hypothesis tests for sampling code: the χ² and Student-t distributions, 2D adaptive
// Simpson integration, Pearson's χ² test with pooling of sparse cells, and the Šidák
// correction for running several tests at one overall significance level.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace nori {

/// Regularized lower incomplete gamma function P(a, x) (Numerical Recipes 3rd ed. §6.2).
double incompleteGammaP(double a, double x);
/// Its complement Q(a, x) = 1 − P(a, x), computed directly so that tiny tail
/// probabilities (p-values of badly wrong samplers) do not round to 0.
double incompleteGammaQ(double a, double x);
/// Regularized incomplete beta function I_x(a, b) (Numerical Recipes 3rd ed. §6.4).
double incompleteBeta(double a, double b, double x);
/// CDF of the χ² distribution with k degrees of freedom: P(k/2, x/2).
double chiSquareCdf(double x, double degreesOfFreedom);
/// CDF of Student's t distribution with ν degrees of freedom.
double studentTCdf(double t, double degreesOfFreedom);
/// Per-test significance level so that `testCount` independent tests together reject a
/// correct sampler with probability `significanceLevel`: 1 − (1 − α)^{1/n}.
double sidakCorrection(double significanceLevel, int testCount);

/// ∫∫ f over [x0,x1]×[y0,y1] by adaptive Simpson quadrature in both dimensions, to
/// relative tolerance `epsilon` with at most `maxDepth` subdivisions per dimension.
double adaptiveSimpson2D(const std::function<double(double, double)> &f, double x0, double y0,
                         double x1, double y1, double epsilon = 1e-6, int maxDepth = 6);

struct ChiSquareResult {
    double statistic = 0.0;
    int degreesOfFreedom = 0;
    int pooledCells = 0; ///< cells merged because their expected count was small
    double pValue = 0.0;
    bool passed = false;
    std::string message; ///< a human-readable account of the test and its verdict
};

/// Pearson's χ² test of observed against expected counts. Cells with an expected count
/// below `minExpFrequency` are pooled (smallest first) until the pool reaches it; a
/// sample in a cell with expected count 0 rejects at once (Nori's chi2_test).
ChiSquareResult pearsonChiSquareTest(const std::vector<double> &observed,
                                     const std::vector<double> &expected, double minExpFrequency,
                                     double significanceLevel);

/// Mean and variance of a stream of values (Welford's algorithm).
struct RunningMoments {
    size_t count = 0;
    double mean = 0.0, m2 = 0.0;
    void add(double value) {
        ++count;
        const double delta = value - mean;
        mean += delta / static_cast<double>(count);
        m2 += delta * (value - mean);
    }
    /// The unbiased sample variance.
    double variance() const { return count > 1 ? m2 / static_cast<double>(count - 1) : 0.0; }
};

struct StudentTResult {
    double t = 0.0;
    double pValue = 0.0;
    bool passed = false;
    std::string message;
};

/// The smallest sample variance the t-test uses (Nori 2's value): a deterministic
/// estimate then passes when |mean − reference| is below about 4·√(1e-5/n), which
/// absorbs the rounding of references given to 4–5 digits.
constexpr double kTTestVarianceFloor = 1e-5;

/// Two-sided one-sample t-test of a Monte Carlo mean (from n samples of the given
/// sample variance) against a reference value, as Nori 2 defines it:
/// t = |mean − reference|·√(n / max(variance, kTTestVarianceFloor)), n − 1 degrees of
/// freedom.
StudentTResult studentTTest(double mean, double variance, size_t sampleCount, double reference,
                            double significanceLevel);

} // namespace nori
