// The agreement test of estimators: a scene rendered by several estimators (an
// integrator with a sampler), each in independent batches of its own seeds; the mean of
// each region of the image is compared between every two estimators in standard errors
// of their difference, estimated from the spread of the batch means (batch means,
// e.g. Law & Kelton, "Simulation Modeling and Analysis", §9.5.3), so that the errors come
// from the renders' own variance and hold for every estimator, photon mappers (whose
// pixels share a photon map) and correlated samplers included.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace nori {

/// A rectangle of pixels whose mean is compared; width 0 is the whole image.
struct ImageRegion {
    std::string name;
    int x = 0, y = 0, width = 0, height = 0;
};

/// An integrator and a sampler, and the samples per pixel of each of its batches.
struct Estimator {
    std::string label;      ///< how tables name it: "path_mats", "volpath/delta", "sobol"
    std::string integrator; ///< the <integrator> element
    std::string sampler = "independent";
    std::string samplerXML; ///< more properties inside <sampler> (adaptive sampling's)
    size_t samplesPerPixel = 16;
    /// Why this estimator cannot have the power the settings ask for in the time a test
    /// has (printed with its comparisons, which then do not fail for lack of power); empty:
    /// it must have that power.
    std::string powerExemption;
};

/// A scene of the battery: its XML without integrator and sampler, the files it reads
/// (written to a temporary folder before it loads) and the regions and estimators that
/// apply. The first estimator is the reference of the table; all are compared pairwise.
struct AgreementScene {
    std::string name;
    std::string body; ///< the XML inside <scene>
    /// The files it reads: name → a function writing the file at the path it is given.
    std::map<std::string, std::function<void(const std::string &path)>> files;
    std::vector<ImageRegion> regions; ///< besides the whole image
    std::vector<Estimator> estimators;
    /// The camera sees mirrors or smooth glass (see Integrator::rendersSpecularInView).
    bool specularInView = false;
};

struct AgreementSettings {
    int batches = 16;         ///< independent renders per estimator
    double sampleScale = 1.0; ///< multiplies every estimator's samples per pixel (soak)
    int threads = 0;          ///< 0: all cores
    double threshold = 4.0;   ///< |difference| in standard errors that still agrees
    /// The relative bias every comparison must be able to see: with the threshold above,
    /// it is detected with probability 95 % (one-sided z of 1.645) when
    /// (threshold + 1.645)·σ_difference ≤ detectableBias·|reference mean|.
    double detectableBias = 0.005;
    /// Where each estimator's mean image goes (SCENE-ESTIMATOR.exr and .png); empty: nowhere.
    std::string pictureFolder;
    uint64_t seed = 1; ///< batch b of estimator e renders with hash(seed, e, b)
    /// Called after each estimator's batches with "scene: estimator (seconds)".
    std::function<void(const std::string &)> progress;
};

/// The mean of a region over the batches of one estimator, and its standard error.
struct RegionEstimate {
    double mean = 0.0, standardError = 0.0;
};

/// One comparison: estimator `estimator` against `other` on one region of one scene.
struct AgreementCell {
    std::string scene, region, estimator, other;
    double difference = 0.0;     ///< estimator − other, relative to other's mean
    double z = 0.0;              ///< the difference in standard errors
    double detectableBias = 0.0; ///< the smallest relative bias seen with 95 % power
    bool agrees = true;          ///< |z| ≤ threshold
    bool powerful = true;        ///< detectableBias ≤ the settings' detectableBias
    std::string powerExemption;  ///< one of the estimators' (see Estimator)
};

struct AgreementReport {
    /// estimates[scene][estimator][region]; region 0 is the whole image.
    std::vector<std::vector<std::vector<RegionEstimate>>> estimates;
    std::vector<AgreementCell> cells; ///< every pair of estimators on every region
    double seconds = 0.0;
    /// No comparison disagrees; with `requirePower`, also none lacks the power asked for
    /// (unless its estimator is exempt).
    bool passed(bool requirePower) const;
    /// The table (rows: scene × region; columns: estimators; cells: z against the
    /// scene's first estimator) and a line per failing comparison.
    std::string table(const std::vector<AgreementScene> &scenes,
                      const AgreementSettings &settings) const;
};

/// Renders every scene with every estimator and compares them. Throws NoriException
/// when a scene does not load (naming it).
AgreementReport runAgreement(const std::vector<AgreementScene> &scenes,
                             const AgreementSettings &settings);

/// The region estimates of one estimator on one scene (settings.batches renders).
std::vector<RegionEstimate> estimateRegions(const AgreementScene &scene, const Estimator &estimator,
                                            int estimatorIndex, const AgreementSettings &settings);

/// Compares two estimates of a region.
AgreementCell compareEstimates(const RegionEstimate &estimate, const RegionEstimate &other,
                               const AgreementSettings &settings);

} // namespace nori
