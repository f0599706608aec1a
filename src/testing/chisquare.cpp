#include <nori/chisquare.h>
#include <nori/pcg32.h>
#include <nori/testsamples.h>

namespace nori {

namespace {

/// Adaptive Simpson's settings for the expected counts: deep enough to resolve a GGX
/// lobe of α = 0.05 (a peak ~1e-3 wide in cos θ) and jumps inside a bin.
constexpr double kQuadratureTolerance = 1e-7;
constexpr int kQuadratureDepth = 12;
constexpr int kSubdivisions = 4;
/// For a bin where the quadrature found nothing but samples fell, at a positive pdf.
constexpr int kFineSubdivisions = 64;

/// The 2D parameterisation of a domain: a point <-> (x, y) in the histogram's rectangle.
struct DomainMap {
    SampleDomain domain;
    double x0, x1, y0, y1; ///< the histogram's rectangle

    explicit DomainMap(SampleDomain domain) : domain(domain) {
        switch (domain) {
        case SampleDomain::UnitSquare:
            x0 = 0, x1 = 1, y0 = 0, y1 = 1;
            break;
        case SampleDomain::CenteredSquare:
            x0 = -1, x1 = 1, y0 = -1, y1 = 1;
            break;
        case SampleDomain::Sphere:
            // (cos θ, φ): dω = d(cos θ) dφ, so equal rectangles are equal solid angles.
            x0 = -1, x1 = 1, y0 = 0, y1 = 2 * kPiDouble;
            break;
        }
    }

    /// The histogram coordinates of a point.
    void toRectangle(const Vector3f &point, double &x, double &y) const {
        if (domain != SampleDomain::Sphere) {
            x = point.x();
            y = point.y();
            return;
        }
        // cos θ of a direction that passed the unit-length check: a float unit vector can
        // have |z| one ulp above 1, which is rounding, not a sample outside the sphere.
        x = std::clamp(static_cast<double>(point.z()), -1.0, 1.0);
        y = std::atan2(static_cast<double>(point.y()), static_cast<double>(point.x()));
        if (y < 0.0)
            y += 2.0 * kPiDouble;
    }

    Vector3f fromRectangle(double x, double y) const {
        if (domain != SampleDomain::Sphere)
            return Vector3f(static_cast<float>(x), static_cast<float>(y), 0.0f);
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - x * x));
        return Vector3f(static_cast<float>(sinTheta * std::cos(y)),
                        static_cast<float>(sinTheta * std::sin(y)), static_cast<float>(x));
    }
};

} // namespace

void ChiSquareOptions::validate() const {
    if (resolution < 2 || resolution > kMaxResolution)
        throw NoriException("'resolution' must lie in [2, {}], got {}", kMaxResolution, resolution);
    if (!(significanceLevel > 0.0 && significanceLevel < 1.0))
        throw NoriException("'significanceLevel' must lie in (0, 1), got {}", significanceLevel);
    if (!(minExpFrequency >= 0.0))
        throw NoriException("'minExpFrequency' must not be negative, got {}", minExpFrequency);
}

ChiSquareReport runChiSquareTest(const SamplingRoutine &routine, const ChiSquareOptions &options) {
    options.validate();
    const DomainMap map(routine.domain);
    ChiSquareReport report;
    report.xBins = options.resolution;
    report.yBins =
        routine.domain == SampleDomain::Sphere ? 2 * options.resolution : options.resolution;
    const size_t binCount = static_cast<size_t>(report.xBins) * report.yBins;
    report.sampleCount =
        scaledTestSamples(options.sampleCount > 0 ? options.sampleCount : 5000 * binCount);
    report.observed.assign(binCount, 0.0);
    report.expected.assign(binCount, 0.0);

    const double binWidth = (map.x1 - map.x0) / report.xBins;
    const double binHeight = (map.y1 - map.y0) / report.yBins;

    // The pdf integrated over a bin, split into `subdivisions`² pieces first: adaptive
    // Simpson refines only where its first samples see detail, so a small light inside a
    // bin would otherwise be missed. The bin is shrunk by a relative 1e-6 and the result
    // scaled back up: densities that jump exactly on a bin edge (a hemisphere at
    // cos θ = 0, a square's border) are never evaluated on the wrong side of the jump.
    auto integrateBin = [&](int bx, int by, int subdivisions) {
        const double dx = 1e-6 * binWidth, dy = 1e-6 * binHeight;
        const double x0 = map.x0 + bx * binWidth + dx, y0 = map.y0 + by * binHeight + dy;
        const double scale = (binWidth * binHeight) / ((binWidth - 2 * dx) * (binHeight - 2 * dy));
        const double pieceWidth = (binWidth - 2 * dx) / subdivisions;
        const double pieceHeight = (binHeight - 2 * dy) / subdivisions;
        double integral = 0.0;
        for (int py = 0; py < subdivisions; ++py)
            for (int px = 0; px < subdivisions; ++px)
                integral += adaptiveSimpson2D(
                    [&](double x, double y) { return routine.pdf(map.fromRectangle(x, y)); },
                    x0 + px * pieceWidth, y0 + py * pieceHeight, x0 + (px + 1) * pieceWidth,
                    y0 + (py + 1) * pieceHeight, kQuadratureTolerance, kQuadratureDepth);
        return integral * scale;
    };

    // The first sample of each bin is kept: if the quadrature finds nothing in a bin
    // that received samples, the pdf at that sample tells a missed sliver (a light's
    // corner across a bin's corner) from a sample the pdf calls impossible.
    std::vector<Vector3f> firstSample(binCount);
    PCG32 random(options.seed, 0x9e3779b97f4a7c15ULL);
    for (size_t i = 0; i < report.sampleCount; ++i) {
        const float u = random.nextFloat();
        Vector3f point;
        if (!routine.sample(Point2f(u, random.nextFloat()), point))
            continue;
        double x = 0.0, y = 0.0;
        if (point.allFinite())
            map.toRectangle(point, x, y);
        const bool inside = point.allFinite() && x >= map.x0 && x <= map.x1 && y >= map.y0 &&
                            y <= map.y1 &&
                            (routine.domain != SampleDomain::Sphere ||
                             std::abs(point.squaredNorm() - 1.0f) < 1e-3f);
        if (!inside) {
            ++report.samplesOutside;
            continue;
        }
        // Points exactly on the far edge belong to the last bin.
        const int cx =
            std::min(static_cast<int>(std::floor((x - map.x0) / binWidth)), report.xBins - 1);
        const int cy =
            std::min(static_cast<int>(std::floor((y - map.y0) / binHeight)), report.yBins - 1);
        const size_t bin = static_cast<size_t>(cy) * report.xBins + cx;
        if (report.observed[bin] == 0.0)
            firstSample[bin] = point;
        report.observed[bin] += 1.0;
    }

    // Expected counts: the pdf integrated over each bin, times the number of samples.
    for (int by = 0; by < report.yBins; ++by)
        for (int bx = 0; bx < report.xBins; ++bx) {
            const size_t bin = static_cast<size_t>(by) * report.xBins + bx;
            double integral = integrateBin(bx, by, kSubdivisions);
            if (integral == 0.0 && report.observed[bin] > 0.0 &&
                routine.pdf(firstSample[bin]) > 0.0)
                integral = integrateBin(bx, by, kFineSubdivisions);
            report.pdfIntegral += integral;
            report.expected[bin] = integral * static_cast<double>(report.sampleCount);
        }

    if (report.samplesOutside > 0) {
        report.result.message = fmt::format(
            "rejected: {} samples lie outside the domain (or are not finite / not unit length)",
            report.samplesOutside);
        return report;
    }
    if (!std::isfinite(report.pdfIntegral)) {
        report.result.message = "rejected: pdf() returns NaN or infinity somewhere in the domain";
        return report;
    }
    // The quadrature is accurate to ~1e-3 for the smooth densities tested here.
    if (report.pdfIntegral > 1.0 + 1e-3) {
        report.result.message =
            fmt::format("rejected: the pdf integrates to {:.4f} over the domain, more than 1",
                        report.pdfIntegral);
        return report;
    }
    report.result = pearsonChiSquareTest(report.observed, report.expected, options.minExpFrequency,
                                         options.significanceLevel);
    return report;
}

} // namespace nori
