/*
 * ttest — Student's t-test of Monte Carlo estimates against reference values, in Nori
 * 2's format. BSDF mode: the albedo of every nested BSDF (mean luminance of sample()'s
 * weight) at every angle of `angles`; `references` lists one value per BSDF and angle,
 * BSDF by BSDF (Nori 2 indexes these wrongly with several BSDFs). Scene mode: the
 * luminance of Li() over a nested scene's (tiny) image, one reference per scene (for an
 * integrator that splats, Li and the sample's splats); the integrator is preprocessed and the sampler seeded as in a render. A scene that names no
 * sampler is sampled by `independent`, Nori 2's default, as its references were made
 * (renders default to `sobol`). The significance level is Šidák-corrected over all tests.
 *
 * Parameters:
 *   significanceLevel  float    0.01    probability of rejecting a correct estimator
 *   angles             string   ""      incident angles in degrees (BSDF mode)
 *   references         string   ""      reference values
 *   sampleCount        integer  100000  samples per estimate (overrides the scenes'; times
 *                                       NORI_TEST_SAMPLE_SCALE, see docs/testing.md)
 *
 *   <test type="ttest">
 *       <string name="angles" value="0, 45, 80"/>
 *       <string name="references" value="0.5, 0.5, 0.5"/>
 *       <bsdf type="diffuse"/>
 *   </test>
 */
#include <nori/bsdf.h>
#include <nori/pcg32.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/strutil.h>
#include <nori/test.h>
#include <nori/testsamples.h>

#include <iostream>

namespace nori {
namespace {

class StudentsTTest : public Test {
public:
    explicit StudentsTTest(const PropertyList &props) {
        m_significanceLevel = props.getFloat("significanceLevel", 0.01f);
        m_angles = toFloatList(props.getString("angles", ""), "'angles'");
        m_references = toFloatList(props.getString("references", ""), "'references'");
        const int sampleCount = props.getInteger("sampleCount", 100000);
        if (sampleCount < 2)
            throw NoriException("ttest: 'sampleCount' must be at least 2, got {}", sampleCount);
        m_sampleCount = scaledTestSamples(static_cast<size_t>(sampleCount));
    }

    using NoriObject::addChild;

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() == EBSDF)
            m_bsdfs.push_back(std::static_pointer_cast<BSDF>(child));
        else if (child->getClassType() == EScene)
            m_scenes.push_back(std::static_pointer_cast<Scene>(child));
        else
            NoriObject::addChild(child, name);
    }

    void activate() override {
        if (!m_bsdfs.empty() && !m_scenes.empty())
            throw NoriException("ttest: cannot test BSDFs and scenes at the same time");
        if (m_bsdfs.empty() && m_scenes.empty())
            throw NoriException("ttest: nothing to test (nest a <bsdf> or a <scene>)");
        const size_t expected =
            m_bsdfs.empty() ? m_scenes.size() : m_bsdfs.size() * m_angles.size();
        if (!m_bsdfs.empty() && m_angles.empty())
            throw NoriException("ttest: BSDF mode needs 'angles'");
        if (m_references.size() != expected)
            throw NoriException(
                "ttest: {} references given, {} expected ({})", m_references.size(), expected,
                m_bsdfs.empty() ? "one per scene" : "one per BSDF and angle, BSDF by BSDF");
    }

    bool run(const TestOptions &) override {
        const int total = static_cast<int>(m_references.size());
        const double alpha = sidakCorrection(m_significanceLevel, total);
        int passed = 0;
        size_t index = 0;
        for (const auto &bsdf : m_bsdfs)
            for (float angle : m_angles) {
                const StudentTResult result =
                    testAlbedo(*bsdf, angle, m_references[index++], alpha);
                std::cout << fmt::format("ttest {} at {} degrees: {}\n", bsdf->toString(), angle,
                                         result.message);
                passed += result.passed ? 1 : 0;
            }
        for (const auto &scene : m_scenes) {
            const StudentTResult result = testScene(*scene, m_references[index++], alpha);
            std::cout << fmt::format("ttest scene with {}: {}\n",
                                     scene->getIntegrator()->toString(), result.message);
            passed += result.passed ? 1 : 0;
        }
        std::cout << fmt::format("ttest: {}/{} passed (significance {:g} over all tests)\n", passed,
                                 total, m_significanceLevel);
        return passed == total;
    }

    std::string toString() const override {
        return fmt::format("StudentsTTest[significanceLevel={}, sampleCount={}]",
                           m_significanceLevel, m_sampleCount);
    }

private:
    StudentTResult testAlbedo(const BSDF &bsdf, float angle, double reference, double alpha) const {
        const float theta = degToRad(angle);
        const Vector3f wi(std::sin(theta), 0.0f, std::cos(theta));
        PCG32 random(static_cast<uint64_t>(angle * 1000.0f), 7);
        RunningMoments moments;
        for (size_t i = 0; i < m_sampleCount; ++i) {
            BSDFQueryRecord bRec(wi);
            const float u = random.nextFloat();
            moments.add(bsdf.sample(bRec, Point2f(u, random.nextFloat())).getLuminance());
        }
        return studentTTest(moments.mean, moments.variance(), moments.count, reference, alpha);
    }

    StudentTResult testScene(Scene &scene, double reference, double alpha) const {
        scene.getIntegrator()->preprocess(&scene);
        std::unique_ptr<Sampler> sampler = scene.hasDefaultSampler()
                                               ? createDefault<Sampler>("independent")->clone()
                                               : scene.getSampler()->clone();
        const Camera *camera = scene.getCamera();
        const Vector2i size = camera->getOutputSize();
        const Integrator &integrator = *scene.getIntegrator();
        RunningMoments moments;
        std::vector<Splat> splats;
        for (size_t i = 0; i < m_sampleCount; ++i) {
            // Each sample is its own "pixel" of the sequence, so samples are independent
            // whatever the sampler does between pixels.
            sampler->generate(Point2i(static_cast<int>(i % 65536), static_cast<int>(i / 65536)));
            const Point2f film = sampler->next2D();
            const Point2f pixel(film.x() * size.x(), film.y() * size.y());
            Ray3f ray;
            Color3f value = scene.sampleCameraRay(ray, pixel, sampler->next2D());
            splats.clear();
            if (!(value == 0.0f).all())
                value *= integrator.splats()
                             ? integrator.LiAndSplats(&scene, sampler.get(), ray, splats)
                             : integrator.Li(&scene, sampler.get(), ray);
            // The image's mean (unfiltered) counts a sample's splats wherever they land
            // (see Splat: the film averages them over the samples of every pixel).
            for (const Splat &splat : splats)
                if (splat.layer == 0) // not an integrator's debug layer
                    value += splat.value;
            moments.add(value.getLuminance());
        }
        return studentTTest(moments.mean, moments.variance(), moments.count, reference, alpha);
    }

    double m_significanceLevel;
    std::vector<float> m_angles, m_references;
    size_t m_sampleCount;
    std::vector<std::shared_ptr<BSDF>> m_bsdfs;
    std::vector<std::shared_ptr<Scene>> m_scenes;
};

NORI_REGISTER_CLASS(StudentsTTest, "ttest");

} // namespace
} // namespace nori
