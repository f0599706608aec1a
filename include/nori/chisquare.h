// The χ² test of a sampling routine against its density: draws samples, bins them over
// the domain, integrates the pdf over every bin for the expected counts and runs
// Pearson's test. It serves the chi2test XML plugin, warptest and the Catch2 tests, for
// warps, BSDFs, phase functions and emitters alike.
#pragma once

#include <nori/bitmap.h>
#include <nori/object.h>
#include <nori/statistics.h>
#include <nori/vector.h>

#include <functional>

namespace nori {

/// Where the samples live and how the histogram covers it.
enum class SampleDomain {
    UnitSquare,     ///< points in [0,1]², resolution × resolution bins
    CenteredSquare, ///< points in [-1,1]² (disks, tents), resolution × resolution bins
    Sphere          ///< unit directions, binned in cos θ × φ: resolution × 2·resolution
                    ///< bins of equal solid angle
};

/// A sampling routine and its density. Points of 2D domains use x and y (z is ignored).
struct SamplingRoutine {
    SampleDomain domain = SampleDomain::Sphere;
    /// Maps a uniform sample to a point; returns false when no point is produced (e.g. a
    /// BSDF that absorbs, or a discrete lobe): such samples are not binned.
    std::function<bool(const Point2f &sample, Vector3f &point)> sample;
    /// The density of `point` (per area or per solid angle), as the sampler claims.
    std::function<double(const Vector3f &point)> pdf;
};

struct ChiSquareOptions {
    /// The finest histogram: 512 × 1024 bins already need 2.6·10⁹ samples at Nori's
    /// default of 5000 per bin.
    static constexpr int kMaxResolution = 512;

    int resolution = 10;          ///< bins along the first axis (Nori's default)
    size_t sampleCount = 0;       ///< 0: 5000 per bin (Nori's default); times testSampleScale()
    double minExpFrequency = 5.0; ///< bins expecting fewer samples are pooled
    double significanceLevel = 0.01;
    uint64_t seed = 0;

    /// Throws NoriException naming the first value out of range.
    void validate() const;
};

struct ChiSquareReport {
    int xBins = 0, yBins = 0;
    std::vector<double> observed; ///< row-major, yBins rows of xBins
    std::vector<double> expected;
    size_t sampleCount = 0;
    size_t samplesOutside = 0; ///< samples outside the domain (a bug in the sampler)
    double pdfIntegral = 0.0;  ///< the pdf's integral over the domain (ideally ≤ 1)
    ChiSquareResult result;
};

/// Runs the test. A sample outside the domain rejects it, as does a pdf that integrates
/// to more than 1 (beyond quadrature error).
ChiSquareReport runChiSquareTest(const SamplingRoutine &routine, const ChiSquareOptions &options);

/// The parameters of a plugin as its toString() lists them ("alpha=0.3, material=Au"
/// from "RoughConductor[alpha=0.3, material=Au]"), for naming pictures.
std::string parameterSetOf(const NoriObject &plugin);
/// A file name (without folder) for the picture of a χ² test: plugin, parameter set and
/// condition (angle, reference point), with characters unsafe in file names replaced,
/// e.g. "roughconductor_alpha=0.3-material=Au_wi-30deg".
std::string chiSquarePictureName(const std::string &plugin, const std::string &parameters,
                                 const std::string &condition);

/// Observed | expected | signed difference, side by side (the first two on the same
/// scale), with labels and the verdict underneath: the picture warptest writes.
Bitmap renderChiSquareReport(const ChiSquareReport &report, const std::string &title);

} // namespace nori
