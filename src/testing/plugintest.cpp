#include "testing/plugintest.h"
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/phase.h>
#include <nori/plugindoc.h>
#include <nori/samplingroutines.h>
#include <nori/shape.h>
#include <nori/warp.h>

#include <filesystem>

namespace nori {

namespace {

/// Samples drawn per case for the value checks (weights, reciprocity, laws, energy).
constexpr int kValueSamples = 20000;
/// Relative tolerance of value comparisons: single-precision evaluation of the same
/// quantity along two paths (a half vector from wi + wo or wo + wi, a weight from one
/// division or another) agrees to ~10 ulps; 1e-3 leaves room for grazing angles.
constexpr float kRelativeTolerance = 1e-3f;
/// Incident angles of BSDF cases (degrees from the normal); from below as 180° − θ.
const float kAngles[] = {0.0f, 30.0f, 60.0f, 85.0f};
/// Samples of an emitter's χ² test. A light covers a few histogram cells, and the
/// quadrature of the expected counts errs by ~0.5% in the cells its silhouette cuts: with
/// Nori's million samples that error alone would reject a correct light (χ² ~ 200 on 8
/// cells). 2·10⁵ samples keep it below the noise and still reject a pdf 3% off (χ² ~ 180).
constexpr size_t kEmitterChiSquareSamples = 200000;

bool close(float a, float b) {
    return std::abs(a - b) <= kRelativeTolerance * std::max(std::abs(a), std::abs(b)) + 1e-7f;
}

bool closeColor(const Color3f &a, const Color3f &b, float slack = 0.0f) {
    auto near = [slack](float x, float y) { return close(x, y) || std::abs(x - y) <= slack; };
    return near(a.r(), b.r()) && near(a.g(), b.g()) && near(a.b(), b.b());
}

/// How much f(wi, ·) changes when wo turns by 1e-5 radians: the rounding error of
/// evaluating f at a badly conditioned pair (Fresnel near total internal reflection
/// varies without bound) is of this size, and a tolerance must allow for it.
float sensitivity(const BSDF &bsdf, const Vector3f &wi, const Vector3f &wo) {
    const Frame frame(wo);
    const Color3f f = bsdf.eval(BSDFQueryRecord(wi, wo, ESolidAngle));
    float change = 0.0f;
    for (const Vector3f &axis : {frame.s, frame.t}) {
        const Vector3f turned = Vector3f(wo + 1e-5f * axis).normalized();
        const Color3f g = bsdf.eval(BSDFQueryRecord(wi, turned, ESolidAngle));
        change = std::max(change, (g - f).abs().maxCoeff());
    }
    return change;
}

bool isUnitDirection(const Vector3f &v) {
    return v.allFinite() && std::abs(v.squaredNorm() - 1.0f) < 1e-3f;
}

bool isValidWeight(const Color3f &weight) {
    return weight.isValid(); // finite and non-negative
}

std::string format(const Vector3f &v) {
    return fmt::format("({:.4f}, {:.4f}, {:.4f})", v.x(), v.y(), v.z());
}

std::string format(const Color3f &c) {
    return fmt::format("({:.5g}, {:.5g}, {:.5g})", c.r(), c.g(), c.b());
}

/// One situation a plugin is tested in (an incident direction, a reference point), with
/// the first problem found there.
struct Case {
    std::string description;
    std::string condition; ///< for picture names, e.g. "wi-30deg"
    std::string problem;   ///< empty while all is well
    void fail(const std::string &message) {
        if (problem.empty())
            problem = message;
    }
};

/// The checks every sample gets: a finite, non-negative weight and, where the weight is
/// not zero, a finite unit direction. False when the sample carries nothing to check
/// further (a failed sample, or a problem now recorded in c).
bool usableSample(const Color3f &weight, const Vector3f &direction, const char *name, Case &c) {
    if (!isValidWeight(weight)) {
        c.fail(fmt::format("sample() returned the weight {} (NaN, infinite or negative)",
                           format(weight)));
        return false;
    }
    if ((weight == 0.0f).all())
        return false;
    if (!isUnitDirection(direction)) {
        c.fail(fmt::format("sample() returned {} = {} with a non-zero weight: not a finite unit "
                           "vector",
                           name, format(direction)));
        return false;
    }
    return true;
}

/// The object of the plugin under test in a loaded example: the example itself, or the
/// BSDF or emitter of a <mesh> example.
std::shared_ptr<NoriObject> subjectOf(const std::shared_ptr<NoriObject> &root,
                                      NoriObject::EClassType type) {
    if (root->getClassType() == type)
        return root;
    if (const auto shape = std::dynamic_pointer_cast<Shape>(root)) {
        if (type == NoriObject::EEmitter && shape->getEmitterPtr())
            return shape->getEmitterPtr();
        if (type == NoriObject::EBSDF)
            return shape->getBSDFPtr();
    }
    throw NoriException("the example's root is a <{}>: it must be the {} itself, or a <mesh> "
                        "carrying it",
                        NoriObject::classTypeName(root->getClassType()),
                        NoriObject::classTypeName(type));
}

/// The plugin `name` of kind `kind` made with its default parameters (for an emitter, on
/// its own or, when it needs a shape, on a sphere), or null with `failure` saying why.
std::shared_ptr<NoriObject> loadWithDefaults(NoriObject::EClassType kind, const std::string &name,
                                             std::string &failure) {
    const std::string tag = NoriObject::classTypeName(kind);
    std::vector<std::string> candidates = {fmt::format("<{} type=\"{}\"/>", tag, name)};
    if (kind == NoriObject::EEmitter)
        candidates.push_back(
            fmt::format("<mesh type=\"sphere\"><float name=\"radius\" value=\"0.5\"/><emitter "
                        "type=\"{}\"/></mesh>",
                        name));
    for (const std::string &xml : candidates) {
        try {
            return loadFromXMLString(xml, NORI_SOURCE_DIR);
        } catch (const NoriException &error) {
            if (failure.empty())
                failure = error.what();
        }
    }
    return nullptr;
}

/// Checks the samples of a BSDF for incident direction wi: directions, weights, laws of
/// discrete lobes, weight = eval·cos/pdf, reciprocity and energy.
void checkBSDFValues(const BSDF &bsdf, const Vector3f &wi, PCG32 &random, Case &c) {
    double energy = 0.0, energy2 = 0.0;
    for (int i = 0; i < kValueSamples && c.problem.empty(); ++i) {
        BSDFQueryRecord bRec(wi);
        const float u = random.nextFloat();
        const Color3f weight = bsdf.sample(bRec, Point2f(u, random.nextFloat()));
        if (!usableSample(weight, bRec.wo, "wo", c))
            continue;
        const bool refracted = Frame::cosTheta(bRec.wo) * Frame::cosTheta(wi) < 0.0f;
        const double albedo = weight.getLuminance() * (refracted ? bRec.eta * bRec.eta : 1.0f);
        energy += albedo;
        energy2 += albedo * albedo;

        if (bRec.measure == EDiscrete) {
            // The law of a delta lobe: mirror reflection about +z, or Snell's law with the
            // eta = η_t/η_i that sample() reports, in the plane of incidence.
            Vector3f expected(-wi.x(), -wi.y(), wi.z());
            if (refracted) {
                const float cosI = Frame::cosTheta(wi);
                const float sin2T = Frame::sinTheta2(wi) / (bRec.eta * bRec.eta);
                const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
                expected =
                    Vector3f(-wi.x() / bRec.eta, -wi.y() / bRec.eta, cosI > 0.0f ? -cosT : cosT);
            }
            if ((bRec.wo - expected).norm() > 1e-3f)
                return c.fail(fmt::format(
                    "a discrete sample went to wo = {}, but {} gives {}", format(bRec.wo),
                    refracted ? fmt::format("Snell's law with eta = {}", bRec.eta)
                              : std::string("mirror reflection"),
                    format(expected)));
            if (!(bsdf.eval(bRec) == 0.0f).all() || bsdf.pdf(bRec) != 0.0f)
                return c.fail("eval() or pdf() is not 0 for a discrete sample: a delta lobe has "
                              "no value or density at any one direction");
            continue;
        }
        if (bRec.measure != ESolidAngle)
            return c.fail("sample() set neither ESolidAngle nor EDiscrete as the measure");
        const float density = bsdf.pdf(bRec);
        const Color3f f = bsdf.eval(bRec);
        if (!(density > 0.0f))
            return c.fail(fmt::format("pdf() is {} at wo = {}, a direction sample() chose", density,
                                      format(bRec.wo)));
        const Color3f expectedWeight = f * (std::abs(Frame::cosTheta(bRec.wo)) / density);
        if (!closeColor(weight, expectedWeight))
            return c.fail(fmt::format("sample() returned the weight {} at wo = {}, but "
                                      "eval·|cos θo|/pdf = {}",
                                      format(weight), format(bRec.wo), format(expectedWeight)));
        // Reciprocity; across a refraction, f(wo, wi) = η² f(wi, wo) with η = η_t/η_i.
        BSDFQueryRecord reverse(bRec.wo, wi, ESolidAngle);
        const Color3f fReverse = bsdf.eval(reverse);
        const float eta2 = refracted ? bRec.eta * bRec.eta : 1.0f;
        const Color3f expectedReverse = f * eta2;
        if (!closeColor(fReverse, expectedReverse, 4.0f * eta2 * sensitivity(bsdf, wi, bRec.wo)))
            return c.fail(fmt::format(
                "not reciprocal: f(wi, wo) = {} but f(wo, wi) = {} for wo "
                "= {}{}",
                format(f), format(fReverse), format(bRec.wo),
                refracted ? fmt::format(" (expected η² f(wi, wo) = {})", format(expectedReverse))
                          : std::string()));
    }
    if (!c.problem.empty())
        return;
    const double mean = energy / kValueSamples;
    const double error =
        std::sqrt(std::max(0.0, energy2 / kValueSamples - mean * mean) / kValueSamples);
    if (mean > 1.0 + 4.0 * error + 1e-3)
        c.fail(fmt::format("the albedo is {:.4f} ± {:.4f}: more energy leaves than arrives", mean,
                           error));
}

void checkPhaseValues(const PhaseFunction &phase, const Vector3f &wi, PCG32 &random, Case &c) {
    for (int i = 0; i < kValueSamples && c.problem.empty(); ++i) {
        PhaseFunctionQueryRecord pRec(wi);
        const float u = random.nextFloat();
        const Color3f weight = phase.sample(pRec, Point2f(u, random.nextFloat()));
        if (!usableSample(weight, pRec.wo, "wo", c))
            continue;
        const float density = phase.pdf(pRec);
        if (!(density > 0.0f))
            return c.fail(fmt::format("pdf() is {} at a direction sample() chose", density));
        const Color3f expected = phase.eval(pRec) / density;
        if (!closeColor(weight, expected))
            return c.fail(fmt::format("sample() returned the weight {}, but eval/pdf = {}",
                                      format(weight), format(expected)));
        const PhaseFunctionQueryRecord reverse(pRec.wo, wi, ESolidAngle);
        if (!closeColor(phase.eval(reverse), phase.eval(pRec)))
            return c.fail(fmt::format("not reciprocal: p(wi, wo) = {} but p(wo, wi) = {}",
                                      format(phase.eval(pRec)), format(phase.eval(reverse))));
    }
}

void checkEmitterValues(const Emitter &emitter, const Point3f &ref, PCG32 &random, Case &c) {
    EmitterQueryRecord first(ref);
    Color3f firstWeight(0.0f);
    for (int i = 0; i < kValueSamples && c.problem.empty(); ++i) {
        EmitterQueryRecord lRec(ref);
        const float u = random.nextFloat();
        const Color3f weight = emitter.sample(lRec, Point2f(u, random.nextFloat()));
        if (!usableSample(weight, lRec.wi, "wi", c))
            continue;
        if (emitter.isDelta()) {
            // A delta light has one direction and one weight from each point.
            if ((firstWeight == 0.0f).all()) {
                first = lRec;
                firstWeight = weight;
            } else if ((lRec.wi - first.wi).norm() > 1e-5f || !closeColor(weight, firstWeight)) {
                return c.fail(fmt::format("a delta light gave two directions or weights from "
                                          "one point: {} {} and {} {}",
                                          format(first.wi), format(firstWeight), format(lRec.wi),
                                          format(weight)));
            }
            continue;
        }
        const float density = emitter.pdf(lRec);
        if (!(density > 0.0f))
            return c.fail(fmt::format("pdf() is {} at a direction sample() chose", density));
        const Color3f expected = emitter.eval(lRec) / density;
        if (!closeColor(weight, expected))
            return c.fail(fmt::format("sample() returned the weight {} toward {}, but "
                                      "eval/pdf = {}",
                                      format(weight), format(lRec.p), format(expected)));
    }
}

/// A reference point from which no more than 5% of the light's samples are seen at
/// grazing angles (|cos| < 0.05 at the light): seen edge-on, a light is a sliver thinner
/// than the quadrature of expected counts can resolve.
Point3f wellConditionedReference(const Emitter &emitter, PCG32 &random) {
    Point3f ref;
    for (int attempt = 0; attempt < 32; ++attempt) {
        ref = emitterReferencePoint(emitter, Point2f(random.nextFloat(), random.nextFloat()));
        if (emitter.isDelta() || !emitter.getShape())
            return ref;
        int grazing = 0;
        for (int i = 0; i < 200; ++i) {
            EmitterQueryRecord lRec(ref);
            const float u = random.nextFloat();
            if (!(emitter.sample(lRec, Point2f(u, random.nextFloat())) == 0.0f).all() &&
                std::abs(lRec.n.dot(lRec.wi)) < 0.05f)
                ++grazing;
        }
        if (grazing <= 10)
            return ref;
    }
    return ref;
}

/// Runs a χ² test of the case's routine; draws its picture when asked or when it fails.
void chiSquare(const SamplingRoutine &routine, const ChiSquareOptions &options,
               const PluginTestOptions &testOptions, const std::string &pictureStem,
               const std::string &title, Case &c, std::string &verdict) {
    const ChiSquareReport report = runChiSquareTest(routine, options);
    verdict = report.result.message;
    if (!report.result.passed)
        c.fail("χ²: " + report.result.message);
    if (!testOptions.pictureFolder.empty() && (testOptions.allPictures || !report.result.passed)) {
        std::filesystem::create_directories(testOptions.pictureFolder);
        const std::string path =
            (std::filesystem::path(testOptions.pictureFolder) / (pictureStem + ".png")).string();
        renderChiSquareReport(report, title).savePNG(path);
        verdict += fmt::format(" [picture: {}]", path);
    }
}

} // namespace

std::vector<std::string> samplingPlugins() {
    std::vector<std::string> names;
    for (const auto &[type, name] : NoriObjectFactory::registeredClasses())
        if (type == NoriObject::EBSDF || type == NoriObject::EPhaseFunction ||
            type == NoriObject::EEmitter)
            names.push_back(name);
    return names;
}

PluginTestResult testSamplingPlugin(const std::string &name, const PluginTestOptions &options) {
    // The sampling plugin of that name (a name may also be, say, a texture's).
    std::vector<NoriObject::EClassType> kinds = NoriObjectFactory::kindsOf(name);
    if (kinds.empty())
        throw NoriException("no plugin is registered as '{}'", name);
    NoriObject::EClassType kind = kinds.front();
    for (NoriObject::EClassType candidate : kinds)
        if (candidate == NoriObject::EBSDF || candidate == NoriObject::EPhaseFunction ||
            candidate == NoriObject::EEmitter)
            kind = candidate;
    const NoriObjectFactory::Entry &entry = NoriObjectFactory::entry(kind, name);
    PluginTestResult result;
    result.report = fmt::format("{} ({}, {})\n", name, NoriObject::classTypeName(entry.type),
                                shortSourcePath(entry.sourceFile));
    if (entry.type != NoriObject::EBSDF && entry.type != NoriObject::EPhaseFunction &&
        entry.type != NoriObject::EEmitter) {
        result.report += "  not a BSDF, phase function, emitter or integrator: nothing to test\n";
        return result;
    }
    const std::string comment = docCommentOf(kind, name);
    PluginDoc doc;
    std::vector<std::shared_ptr<NoriObject>> roots, subjects;
    const bool ours = isShippedPlugin(kind, name);
    if (!ours && comment.empty()) {
        // A user's plugin (a course file dropped into plugins/course/) without a doc comment
        // that gives examples is tested at its default parameters; one that does not load
        // with them is listed as not tested, never failed.
        std::string failure;
        std::shared_ptr<NoriObject> root = loadWithDefaults(kind, name, failure);
        if (!root) {
            result.report += fmt::format(
                "  not tested: it has no doc comment giving examples, and it does not load "
                "with its default parameters ({}); docs/nori2.md says how to write one\n",
                failure);
            return result;
        }
        result.report += "  no doc comment: tested at its default parameters (a doc comment's "
                         "examples test others; docs/nori2.md says how)\n";
        roots.push_back(root);
        subjects.push_back(subjectOf(root, entry.type));
    } else if (!ours) {
        try {
            doc = parsePluginDoc(comment);
        } catch (const NoriException &error) {
            result.report +=
                fmt::format("  not tested: the comment its file starts with is no doc comment "
                            "({}); docs/nori2.md says how to write one\n",
                            error.what());
            return result;
        }
    } else if (comment.empty()) {
        throw NoriException("{}: '{}' has no doc comment, so no examples to test (see "
                            "include/nori/plugindoc.h)",
                            entry.sourceFile, name);
    } else {
        doc = parsePluginDoc(comment);
    }
    if (!doc.exemption.empty()) {
        result.report += "  exempt: " + doc.exemption + "\n";
        return result;
    }
    if (subjects.empty() && doc.examples.empty())
        throw NoriException("{}: the doc comment of '{}' has no example to test", entry.sourceFile,
                            name);
    result.tested = true;

    // Load every example first: the χ² tests of the plugin share one significance level.
    for (const std::string &example : doc.examples) {
        try {
            roots.push_back(loadFromXMLString(example, NORI_SOURCE_DIR));
        } catch (const NoriException &error) {
            throw NoriException("{}: an example of '{}' does not load: {}", entry.sourceFile, name,
                                error.what());
        }
        subjects.push_back(subjectOf(roots.back(), entry.type));
    }
    const bool isBSDF = entry.type == NoriObject::EBSDF;
    const int casesPerExample = isBSDF ? 2 * static_cast<int>(std::size(kAngles)) : 4;
    ChiSquareOptions chi2;
    chi2.significanceLevel = sidakCorrection(options.significanceLevel,
                                             casesPerExample * static_cast<int>(subjects.size()));

    PCG32 random(options.seed, 0x5A3D);
    for (size_t e = 0; e < subjects.size(); ++e) {
        const NoriObject &subject = *subjects[e];
        const std::string parameters = parameterSetOf(subject);
        result.report += fmt::format("  example {}: {}\n", e + 1, subject.toString());
        for (int k = 0; k < casesPerExample; ++k) {
            Case c;
            SamplingRoutine routine;
            bool hasDensity = true;
            if (isBSDF) {
                // Angles from above, then the same from below (for transmission).
                const float angle = kAngles[k % std::size(kAngles)];
                const float theta = degToRad(k < 4 ? angle : 180.0f - angle), phi = 0.3f;
                const Vector3f wi(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                  std::cos(theta));
                c.description = fmt::format("wi at {:g}°", radToDeg(theta));
                c.condition = fmt::format("wi-{:g}deg", radToDeg(theta));
                checkBSDFValues(static_cast<const BSDF &>(subject), wi, random, c);
                routine = bsdfRoutine(static_cast<const BSDF &>(subject), wi);
            } else if (entry.type == NoriObject::EPhaseFunction) {
                const Vector3f wi =
                    Warp::squareToUniformSphere(Point2f(random.nextFloat(), random.nextFloat()));
                c.description = fmt::format("wi = {}", format(wi));
                c.condition = fmt::format("wi-{}", k + 1);
                checkPhaseValues(static_cast<const PhaseFunction &>(subject), wi, random, c);
                routine = phaseRoutine(static_cast<const PhaseFunction &>(subject), wi);
            } else {
                const auto &emitter = static_cast<const Emitter &>(subject);
                const Point3f ref = wellConditionedReference(emitter, random);
                c.description = fmt::format("seen from {}", format(ref));
                c.condition = fmt::format("ref-{}", k + 1);
                checkEmitterValues(emitter, ref, random, c);
                hasDensity = !emitter.isDelta();
                if (hasDensity)
                    routine = emitterRoutine(emitter, ref);
            }
            std::string verdict = "no density (delta light): its law was checked";
            if (hasDensity) {
                chi2.seed = random.nextUInt();
                chi2.sampleCount = isBSDF || entry.type == NoriObject::EPhaseFunction
                                       ? 0
                                       : kEmitterChiSquareSamples;
                chiSquare(routine, chi2, options,
                          chiSquarePictureName(name, parameters, c.condition),
                          fmt::format("{} {}", subject.toString(), c.condition), c, verdict);
            }
            result.passed &= c.problem.empty();
            result.report +=
                fmt::format("    {}: {}\n", c.description,
                            c.problem.empty() ? "pass; " + verdict : "FAIL: " + c.problem);
        }
    }
    result.report += fmt::format("  verdict: {}\n", result.passed ? "pass" : "FAIL");
    return result;
}

std::vector<PluginTestResult> testSamplingPlugins(const std::vector<std::string> &names,
                                                  const PluginTestOptions &options) {
    std::vector<PluginTestResult> results(names.size());
    parallelFor(size_t(0), names.size(),
                [&](size_t i) { results[i] = testSamplingPlugin(names[i], options); });
    return results;
}

} // namespace nori
