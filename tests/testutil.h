// Helpers shared by the Catch2 tests: temporary folders, files, and running `nori`.
#pragma once

#include "testing/agreement.h"

#include <nori/chisquare.h>
#include <nori/object.h>
#include <nori/pcg32.h>
#include <nori/render.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/testsamples.h>
#include <nori/warp.h>

#include <filesystem>
#include <string>

namespace nori::testing {

/// A fresh directory under the system's temp folder, removed with its content.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;

    const std::filesystem::path &path() const { return m_path; }
    /// Writes `content` to path()/relativeName (creating folders) and returns the path.
    std::string write(const std::string &relativeName, const std::string &content) const;

private:
    std::filesystem::path m_path;
};

/// The outcome of running a program: its exit status and what it printed.
struct ProcessResult {
    int exitCode = -1;  ///< exit status, or 128 + signal number if killed
    std::string output; ///< stdout and stderr, interleaved
};

/// Runs `nori` with the arguments. If `interruptAfter` is non-empty, sends SIGINT
/// once that text has appeared in the output.
ProcessResult runNori(const std::vector<std::string> &arguments,
                      const std::string &interruptAfter = "");
/// Runs `nori` and kills it with SIGKILL once `seconds` have passed, if it still runs
/// (what an out-of-memory kill, a preemption or a power cut does).
ProcessResult runNoriKilledAfter(const std::vector<std::string> &arguments, double seconds);
/// The same for another program (its path).
ProcessResult runCommand(const std::string &program, const std::vector<std::string> &arguments,
                         const std::string &interruptAfter = "");

/// `bytes` compressed as a gzip stream (for .ply.gz and .pbrt.gz files made in tests).
std::string gzip(const std::string &bytes);

/// The scene of an XML text (files relative to `directory`); throws when it is not one.
std::shared_ptr<Scene> loadScene(const std::string &xml, const std::string &directory = ".");

/// Render options for tests: `threads` threads, no progress bar.
RenderOptions quietOptions(int threads);

/// A scene for closed-form lighting tests: a 1×1 camera with a tiny field of view looking
/// at the origin of a 2000×2000 diffuse floor (albedo 0.5, normal +y) from (0.3, 2, 1),
/// rendered by `integrator`, with `content` (lights, more shapes) added.
std::shared_ptr<Scene> litFloor(const std::string &integrator, const std::string &content);

/// Mean and variance of the luminance of `count` samples (times testSampleScale()) of the
/// scene's camera through its integrator (for 1×1 images whose pixel is one estimate),
/// with independent samples.
RunningMoments estimatePixel(Scene &scene, size_t count);

/// A t-test (significance 0.01) of `samples` estimates of a 1×1 image against `reference`.
struct PixelTTest {
    RunningMoments moments;
    StudentTResult result;
    double reference = 0.0;
    /// "estimate m (variance v), reference r, t = t", for the test's INFO.
    std::string summary() const;
};
PixelTTest tTestPixel(Scene &scene, double reference, size_t samples);

/// The χ² test of a sampling routine with 3·10⁵ samples over Nori's default 10 × 20
/// histogram (150 per cell), at significance `level` (Šidák-corrected by the caller).
ChiSquareReport chiSquare(const SamplingRoutine &routine, uint64_t seed, double level);

/// A variant of a scene (another light sampling, say) against the scene it must agree
/// with, and a control: the variant made deliberately wrong, which must not agree. Each
/// scene is rendered by its first estimator (seeds 0, 1 and 2); one cell per region.
struct VariantAgreement {
    std::vector<AgreementCell> variant, control;
    /// "variant: z SE; control: z SE; detectable bias (%): b" of one region, for INFO.
    std::string summary(size_t region) const;
};
VariantAgreement compareVariant(const AgreementScene &reference, const AgreementScene &variant,
                                const AgreementScene &control, const AgreementSettings &settings);

/// Whether two images have the same size and bit-identical pixels.
bool identicalImages(const Bitmap &a, const Bitmap &b);

/// The unit direction at `degrees` from the normal +z (beyond 90: from inside) and at
/// `azimuth` radians about it: the incident directions of BSDF tests.
inline Vector3f incidentDirection(float degrees, float azimuth = 0.0f) {
    const float theta = degToRad(degrees);
    return Vector3f(std::sin(theta) * std::cos(azimuth), std::sin(theta) * std::sin(azimuth),
                    std::cos(theta));
}

/// A direction drawn uniformly on the unit sphere.
inline Vector3f randomDirection(PCG32 &random) {
    return Warp::squareToUniformSphere(Point2f(random.nextFloat(), random.nextFloat()));
}

/// A point drawn uniformly in the cube [-halfSide, halfSide]^3.
inline Point3f randomPoint(PCG32 &random, float halfSide) {
    const float x = 2.0f * random.nextFloat() - 1.0f, y = 2.0f * random.nextFloat() - 1.0f;
    return halfSide * Point3f(x, y, 2.0f * random.nextFloat() - 1.0f);
}

/// The distance from point p to the line of the ray.
inline float distanceToRay(const Point3f &p, const Ray3f &ray) {
    const Vector3f d = ray.d.normalized();
    const Vector3f offset = p - ray.o;
    return (offset - offset.dot(d) * d).norm();
}

/// Registers a plugin for the lifetime of the object.
struct TemporaryPlugin {
    TemporaryPlugin(const std::string &name, NoriObject::EClassType type,
                    const NoriObjectFactory::Constructor &constructor)
        : name(name) {
        NoriObjectFactory::registerClass(name, type, constructor, __FILE__);
    }
    ~TemporaryPlugin() { NoriObjectFactory::unregisterClass(name); }
    TemporaryPlugin(const TemporaryPlugin &) = delete;
    TemporaryPlugin &operator=(const TemporaryPlugin &) = delete;
    std::string name;
};

/// Welch's two-sample t-test at significance 0.01: whether two estimates agree (`t`
/// receives their difference in standard errors).
bool samplesAgree(const RunningMoments &a, const RunningMoments &b, double &t);

/// The message of the NoriException thrown by f, or "" if none was thrown.
template <typename F> std::string errorOf(F &&f) {
    try {
        f();
    } catch (const NoriException &error) {
        return error.what();
    }
    return "";
}

} // namespace nori::testing
