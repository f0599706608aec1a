/*
 * chi2test — Pearson's χ² test that sample() draws from pdf(), in Nori 2's format, for
 * every nested BSDF, phase function and emitter (an area light is given as the <mesh>
 * it is nested in). Each is tested `testCount` times (BSDFs
 * and phase functions for random incident directions, emitters from random reference
 * points); the significance level is Šidák-corrected over all tests. The picture of each
 * failing test (of every test with nori --all-pictures) is written next to the XML file
 * (or to nori --pictures DIR), named after the plugin, its parameters and the angle.
 *
 * Parameters:
 *   significanceLevel  float    0.01   probability of rejecting a correct sampler
 *   resolution         integer  10     bins in cos θ (φ gets twice as many), at most 512
 *   minExpFrequency    integer  5      bins expecting fewer samples are pooled
 *   sampleCount        integer  -1     samples per test; -1: 5000 per bin (Nori's default);
 *                                      times NORI_TEST_SAMPLE_SCALE (docs/testing.md)
 *   testCount          integer  5      tests per plugin
 *   seed               integer  0      seed of the test's random numbers
 *
 *   <test type="chi2test">
 *       <bsdf type="diffuse"/>
 *   </test>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/pcg32.h>
#include <nori/phase.h>
#include <nori/samplingroutines.h>
#include <nori/shape.h>
#include <nori/test.h>
#include <nori/warp.h>

#include <filesystem>
#include <iostream>

namespace nori {
namespace {

class ChiSquareTestPlugin : public Test {
public:
    explicit ChiSquareTestPlugin(const PropertyList &props) {
        m_options.significanceLevel = props.getFloat("significanceLevel", 0.01f);
        m_options.resolution = props.getInteger("resolution", 10);
        m_options.minExpFrequency = props.getInteger("minExpFrequency", 5);
        const int sampleCount = props.getInteger("sampleCount", -1);
        m_testCount = props.getInteger("testCount", 5);
        m_options.seed = static_cast<uint64_t>(props.getInteger("seed", 0));
        m_options.validate();
        if (m_testCount < 1)
            throw NoriException("chi2test: 'testCount' must be at least 1, got {}", m_testCount);
        if (sampleCount == 0 || sampleCount < -1)
            throw NoriException("chi2test: 'sampleCount' must be positive (or -1 for 5000 per "
                                "bin), got {}",
                                sampleCount);
        // Nori's default: 5000 samples per bin of the cos θ × φ grid.
        const size_t resolution = static_cast<size_t>(m_options.resolution);
        m_options.sampleCount =
            sampleCount > 0 ? static_cast<size_t>(sampleCount) : 2 * resolution * resolution * 5000;
    }

    using NoriObject::addChild;

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        switch (child->getClassType()) {
        case EBSDF:
        case EPhaseFunction:
        case EEmitter:
            m_subjects.push_back(child);
            break;
        case EMesh: {
            // A shape carrying an area light: test that light (its sampling needs the shape).
            auto shape = std::dynamic_pointer_cast<Shape>(child);
            auto emitter = shape ? shape->getEmitterPtr() : nullptr;
            if (!emitter)
                throw NoriException("chi2test: a nested <mesh> must carry an <emitter> to test");
            m_subjects.push_back(emitter);
            m_shapes.push_back(child);
            break;
        }
        default:
            NoriObject::addChild(child, name);
        }
    }

    void activate() override {
        if (m_subjects.empty())
            throw NoriException("chi2test: nothing to test (nest a <bsdf>, <phase> or <emitter>)");
    }

    bool run(const TestOptions &testOptions) override {
        const int total = static_cast<int>(m_subjects.size()) * m_testCount;
        ChiSquareOptions options = m_options;
        options.significanceLevel = sidakCorrection(m_options.significanceLevel, total);
        PCG32 random(m_options.seed, 0xC0FFEE);
        int passed = 0;
        for (const auto &subject : m_subjects) {
            for (int i = 0; i < m_testCount; ++i) {
                std::string what, condition;
                SamplingRoutine routine = routineFor(*subject, random, what, condition);
                options.seed = random.nextUInt();
                const ChiSquareReport report = runChiSquareTest(routine, options);
                std::cout << fmt::format("chi2test {}: {}\n", what, report.result.message);
                if (!testOptions.pictureFolder.empty() &&
                    (testOptions.allPictures || !report.result.passed)) {
                    const std::string picture =
                        (std::filesystem::path(testOptions.pictureFolder) /
                         (chiSquarePictureName(subject->pluginName(), parameterSetOf(*subject),
                                               condition) +
                          ".png"))
                            .string();
                    std::filesystem::create_directories(testOptions.pictureFolder);
                    const std::string title = subject->toString() + " " + condition;
                    renderChiSquareReport(report, title).savePNG(picture);
                    std::cout << fmt::format("chi2test picture: {}\n", picture);
                    if (testOptions.pictureWritten)
                        testOptions.pictureWritten(picture, title);
                }
                passed += report.result.passed ? 1 : 0;
            }
        }
        std::cout << fmt::format("chi2test: {}/{} passed (significance {:g} over all tests)\n",
                                 passed, total, m_options.significanceLevel);
        return passed == total;
    }

    std::string toString() const override {
        return fmt::format("ChiSquareTest[significanceLevel={}, resolution={}, "
                           "minExpFrequency={}, sampleCount={}, testCount={}]",
                           m_options.significanceLevel, m_options.resolution,
                           m_options.minExpFrequency, m_options.sampleCount, m_testCount);
    }

private:
    /// The routine of one test of `subject`, with a random incident direction or
    /// reference point; `what` describes it for the report.
    SamplingRoutine routineFor(const NoriObject &subject, PCG32 &random, std::string &what,
                               std::string &condition) const {
        const Point2f u(random.nextFloat(), random.nextFloat());
        if (subject.getClassType() == EBSDF) {
            // Incident directions in the upper hemisphere, cos θ uniform (as Nori).
            const Vector3f wi = Warp::squareToUniformHemisphere(u);
            what = fmt::format("{} for wi = ({:.3f}, {:.3f}, {:.3f})", subject.toString(), wi.x(),
                               wi.y(), wi.z());
            condition = fmt::format("wi-{:.1f}deg-phi-{:.0f}deg", radToDeg(std::acos(wi.z())),
                                    radToDeg(std::atan2(wi.y(), wi.x())));
            return bsdfRoutine(static_cast<const BSDF &>(subject), wi);
        }
        if (subject.getClassType() == EPhaseFunction) {
            const Vector3f wi = Warp::squareToUniformSphere(u);
            what = fmt::format("{} for wi = ({:.3f}, {:.3f}, {:.3f})", subject.toString(), wi.x(),
                               wi.y(), wi.z());
            condition = fmt::format("wi-{:.1f}deg-phi-{:.0f}deg",
                                    radToDeg(std::acos(std::clamp(wi.z(), -1.0f, 1.0f))),
                                    radToDeg(std::atan2(wi.y(), wi.x())));
            return phaseRoutine(static_cast<const PhaseFunction &>(subject), wi);
        }
        const auto &emitter = static_cast<const Emitter &>(subject);
        const Point3f ref = emitterReferencePoint(emitter, u);
        what = fmt::format("{} from ref = ({:.3f}, {:.3f}, {:.3f})", subject.toString(), ref.x(),
                           ref.y(), ref.z());
        condition = fmt::format("ref-{:.2f}-{:.2f}-{:.2f}", ref.x(), ref.y(), ref.z());
        return emitterRoutine(emitter, ref);
    }

    ChiSquareOptions m_options;
    int m_testCount;
    std::vector<std::shared_ptr<NoriObject>> m_subjects;
    std::vector<std::shared_ptr<NoriObject>> m_shapes; ///< keep area lights' shapes alive
};

NORI_REGISTER_CLASS(ChiSquareTestPlugin, "chi2test");

} // namespace
} // namespace nori
