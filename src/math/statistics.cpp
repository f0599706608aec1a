#include <nori/common.h>
#include <nori/statistics.h>

#include <numeric>

namespace nori {

namespace {

constexpr double kTiny = 1e-300;
constexpr double kRelativeEpsilon = 1e-15;
constexpr int kMaxIterations = 100000;

/// Lentz's guard against division by zero in continued fractions (NR eq. 5.2.21).
double avoidZero(double value) {
    return std::abs(value) < kTiny ? kTiny : value;
}

/// P(a, x) by its series, for x < a + 1 (NR 3rd ed. eq. 6.2.5).
double gammaSeries(double a, double x) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < kMaxIterations; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * kRelativeEpsilon)
            break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/// Q(a, x) = 1 − P(a, x) by Lentz's continued fraction, for x ≥ a + 1 (NR eq. 6.2.7).
double gammaContinuedFraction(double a, double x) {
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        d = avoidZero(d);
        c = b + an / c;
        c = avoidZero(c);
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < kRelativeEpsilon)
            break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

/// The continued fraction of I_x(a, b) (NR 3rd ed. eq. 6.4.5, Lentz's method).
double betaContinuedFraction(double a, double b, double x) {
    const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
    double c = 1.0, d = 1.0 - qab * x / qap;
    d = avoidZero(d);
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m < kMaxIterations; ++m) {
        const int m2 = 2 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = avoidZero(d);
        c = 1.0 + aa / c;
        c = avoidZero(c);
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = avoidZero(d);
        c = 1.0 + aa / c;
        c = avoidZero(c);
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < kRelativeEpsilon)
            break;
    }
    return h;
}

/// One level of adaptive Simpson in 1D, given the endpoint and midpoint values.
double adaptiveSimpson(const std::function<double(double)> &f, double a, double b, double fa,
                       double fm, double fb, double whole, double epsilon, int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const double flm = f(lm), frm = f(rm);
    const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    const double refined = left + right;
    // Richardson: the error of the refined estimate is about (refined − whole)/15.
    if (depth <= 0 || std::abs(refined - whole) <= 15.0 * epsilon)
        return refined + (refined - whole) / 15.0;
    return adaptiveSimpson(f, a, m, fa, flm, fm, left, 0.5 * epsilon, depth - 1) +
           adaptiveSimpson(f, m, b, fm, frm, fb, right, 0.5 * epsilon, depth - 1);
}

double adaptiveSimpson1D(const std::function<double(double)> &f, double a, double b, double epsilon,
                         int maxDepth) {
    const double fa = f(a), fm = f(0.5 * (a + b)), fb = f(b);
    const double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    return adaptiveSimpson(f, a, b, fa, fm, fb, whole, epsilon, maxDepth);
}

} // namespace

double incompleteGammaP(double a, double x) {
    if (x <= 0.0)
        return 0.0;
    return x < a + 1.0 ? gammaSeries(a, x) : 1.0 - gammaContinuedFraction(a, x);
}

double incompleteGammaQ(double a, double x) {
    if (x <= 0.0)
        return 1.0;
    return x < a + 1.0 ? 1.0 - gammaSeries(a, x) : gammaContinuedFraction(a, x);
}

double incompleteBeta(double a, double b, double x) {
    if (x <= 0.0)
        return 0.0;
    if (x >= 1.0)
        return 1.0;
    const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                  a * std::log(x) + b * std::log1p(-x));
    // The continued fraction converges fast for x < (a+1)/(a+b+2); use symmetry otherwise.
    if (x < (a + 1.0) / (a + b + 2.0))
        return front * betaContinuedFraction(a, b, x) / a;
    return 1.0 - front * betaContinuedFraction(b, a, 1.0 - x) / b;
}

double chiSquareCdf(double x, double degreesOfFreedom) {
    return incompleteGammaP(0.5 * degreesOfFreedom, 0.5 * x);
}

double studentTCdf(double t, double degreesOfFreedom) {
    // P(T > |t|) = I_{ν/(ν+t²)}(ν/2, 1/2) / 2.
    const double tail = 0.5 * incompleteBeta(0.5 * degreesOfFreedom, 0.5,
                                             degreesOfFreedom / (degreesOfFreedom + t * t));
    return t >= 0.0 ? 1.0 - tail : tail;
}

double sidakCorrection(double significanceLevel, int testCount) {
    return 1.0 - std::pow(1.0 - significanceLevel, 1.0 / std::max(testCount, 1));
}

double adaptiveSimpson2D(const std::function<double(double, double)> &f, double x0, double y0,
                         double x1, double y1, double epsilon, int maxDepth) {
    // Nested 1D quadratures: the outer one integrates the inner integral over x.
    auto inner = [&](double y) {
        return adaptiveSimpson1D([&](double x) { return f(x, y); }, x0, x1, epsilon, maxDepth);
    };
    return adaptiveSimpson1D(inner, y0, y1, epsilon, maxDepth);
}

ChiSquareResult pearsonChiSquareTest(const std::vector<double> &observed,
                                     const std::vector<double> &expected, double minExpFrequency,
                                     double significanceLevel) {
    ChiSquareResult result;
    std::vector<size_t> order(expected.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return expected[a] < expected[b]; });

    double pooledObserved = 0.0, pooledExpected = 0.0;
    int cells = 0;
    for (size_t index : order) {
        if (expected[index] == 0.0) {
            if (observed[index] > 0.0) {
                result.message = fmt::format(
                    "rejected: {} samples fell in a cell where the pdf integrates to 0 (the "
                    "sampler produces values the pdf says are impossible)",
                    observed[index]);
                return result;
            }
            continue;
        }
        if (expected[index] < minExpFrequency) {
            pooledObserved += observed[index];
            pooledExpected += expected[index];
            ++result.pooledCells;
            if (pooledExpected < minExpFrequency)
                continue;
            // The pool is large enough: it counts as one cell.
            const double diff = pooledObserved - pooledExpected;
            result.statistic += diff * diff / pooledExpected;
            pooledObserved = pooledExpected = 0.0;
            ++cells;
            continue;
        }
        const double diff = observed[index] - expected[index];
        result.statistic += diff * diff / expected[index];
        ++cells;
    }
    if (pooledExpected > 0.0) {
        // A remaining small pool joins the statistic as it is.
        const double diff = pooledObserved - pooledExpected;
        result.statistic += diff * diff / pooledExpected;
        ++cells;
    }
    result.degreesOfFreedom = cells - 1;
    const double totalObserved = std::accumulate(observed.begin(), observed.end(), 0.0);
    const double totalExpected = std::accumulate(expected.begin(), expected.end(), 0.0);
    if (totalObserved == 0.0 && totalExpected == 0.0) {
        // Nothing sampled and nothing expected (light from below a reflector): consistent.
        result.passed = true;
        result.pValue = 1.0;
        result.message = "accepted: no samples, and the pdf is 0 everywhere";
        return result;
    }
    if (result.degreesOfFreedom <= 0) {
        result.message = "rejected: fewer than two cells with enough expected samples (increase "
                         "the sample count or lower the resolution)";
        return result;
    }
    // The upper tail of χ²: Q(k/2, x/2).
    result.pValue = incompleteGammaQ(0.5 * result.degreesOfFreedom, 0.5 * result.statistic);
    result.passed = result.pValue > significanceLevel;
    result.message = fmt::format(
        "chi^2 = {:.2f} with {} degrees of freedom ({} sparse cells pooled): p-value {:.4g} {} "
        "significance level {:.4g}: {}",
        result.statistic, result.degreesOfFreedom, result.pooledCells, result.pValue,
        result.passed ? ">" : "<=", significanceLevel,
        result.passed ? "accepted" : "rejected (sample() does not draw from pdf())");
    return result;
}

StudentTResult studentTTest(double mean, double variance, size_t sampleCount, double reference,
                            double significanceLevel) {
    StudentTResult result;
    const double n = static_cast<double>(sampleCount);
    // Nori 2's statistic (src/ttest.cpp): the variance is floored at kTTestVarianceFloor,
    // so deterministic estimators are compared with references rounded to 4–5 digits.
    result.t = std::abs(mean - reference) * std::sqrt(n / std::max(variance, kTTestVarianceFloor));
    // Two-sided: P(|T| > t) = I_{ν/(ν+t²)}(ν/2, 1/2), without cancellation.
    const double nu = n - 1.0;
    result.pValue = incompleteBeta(0.5 * nu, 0.5, nu / (nu + result.t * result.t));
    result.passed = result.pValue > significanceLevel;
    result.message = fmt::format("mean {:.6g} vs reference {:.6g} (variance {:.3g}, floored at "
                                 "{:g}; t = {:.3f}): p-value {:.4g} {} {:.4g}: {}",
                                 mean, reference, variance, kTTestVarianceFloor, result.t,
                                 result.pValue, result.passed ? ">" : "<=", significanceLevel,
                                 result.passed ? "accepted" : "rejected");
    return result;
}

} // namespace nori
