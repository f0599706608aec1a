// The agreement machinery (src/testing/agreement.h): comparisons in standard errors, and
// planted biases of 0.5 % that it must see on the scenes where it has that power.
#include "testing/agreementscenes.h"
#include "testutil.h"

#include <nori/camera.h>
#include <nori/hash.h>
#include <nori/integrator.h>
#include <nori/photonmap.h>
#include <nori/proplist.h>
#include <nori/sampler.h>
#include <nori/scene.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <iostream>

using namespace nori;

namespace {

/// The matrix's scene of that name.
AgreementScene matrixScene(const std::string &name) {
    const std::vector<AgreementScene> scenes = agreementMatrixScenes();
    const auto found = std::find_if(scenes.begin(), scenes.end(),
                                    [&](const AgreementScene &s) { return s.name == name; });
    REQUIRE(found != scenes.end());
    return *found;
}

/// `scene` with the first occurrence of `from` in its XML replaced by `to`.
AgreementScene planted(AgreementScene scene, const std::string &from, const std::string &to) {
    const size_t at = scene.body.find(from);
    REQUIRE(at != std::string::npos);
    scene.body.replace(at, from.size(), to);
    return scene;
}

/// A negative control: progressive photon mapping with a student's slip in the radius
/// update (Hachisuka & Jensen 2009, §4): each sample's estimate, gathered within the
/// pixel's radius R, is normalised by the radius the update makes of it afterwards,
/// R²·(N + αM)/(N + M), as if the radius were shrunk before the photons were counted.
/// The estimate is (N + M)/(N + αM) times too bright: (1 − α)/α = 43 % in the first pass,
/// fading as N grows (+7.7 % over the Cornell box's 64 passes at α = 0.7, measured).
class PlantedRadiusUpdate : public Integrator {
public:
    explicit PlantedRadiusUpdate(const PropertyList &props)
        : m_parameters(PhotonMappingParameters::read(props, "planted_radius_update")) {}

    void preprocess(const Scene *scene) override {
        m_radii = ProgressiveRadii(scene->getCamera()->getOutputSize(),
                                   photonGatherRadius(*scene, m_parameters.photonRadius));
        beginPass(scene, 0, 1);
    }
    void beginPass(const Scene *scene, uint32_t firstSample, uint32_t) override {
        if (firstSample != m_mapSample)
            m_map = tracePhotons(*scene, m_parameters.photonCount,
                                 hashValues(scene->getSampler()->getSeed(), firstSample));
        m_mapSample = firstSample;
    }
    void endPass(const Scene *) override {
        m_radii.endPass(kAlpha);
        m_mapSample = UINT32_MAX;
    }
    size_t maxSamplesPerPass() const override { return 1; }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        ProgressiveRadii::Pixel *pixel = m_radii.pixel(sampler->pixel());
        if (!pixel)
            return photonMappedRadiance(*scene, m_map, *sampler, ray, m_radii.initialRadius(),
                                        m_parameters.splitBounces, nullptr);
        float found = 0.0f;
        const Color3f radiance =
            photonMappedRadiance(*scene, m_map, *sampler, ray, std::sqrt(pixel->radiusSquared),
                                 m_parameters.splitBounces, &found);
        const float shrinkage = ProgressiveRadii::shrinkage(pixel->photons, found, kAlpha);
        pixel->passPhotons += found;
        ++pixel->passSamples;
        return found > 0.0f ? Color3f(radiance / shrinkage) : radiance; // the slip
    }

    std::string toString() const override { return "PlantedRadiusUpdate[]"; }

private:
    static constexpr float kAlpha = 0.7f;
    PhotonMappingParameters m_parameters;
    mutable ProgressiveRadii m_radii;
    PhotonMap m_map;
    uint32_t m_mapSample = UINT32_MAX;
};

} // namespace

TEST_CASE("Agreement cells: z, power and the rounding floor", "[agreement]") {
    AgreementSettings settings;
    const AgreementCell cell = compareEstimates({1.01, 0.003}, {1.0, 0.004}, settings);
    CHECK(cell.z == Approx(0.01 / 0.005));
    CHECK(cell.difference == Approx(0.01));
    CHECK(cell.agrees);
    // (4 + 1.645)·0.005 / 1.0 = 2.8 %: far from the 0.5 % asked for.
    CHECK(cell.detectableBias == Approx(5.645 * 0.005));
    CHECK_FALSE(cell.powerful);
    // Negative control: the same difference with a tenth of the error disagrees.
    CHECK_FALSE(compareEstimates({1.01, 0.0003}, {1.0, 0.0004}, settings).agrees);
    // Noiseless regions (a sky seen directly) agree up to float rounding, not beyond.
    CHECK(compareEstimates({0.1 * (1 + 3e-6), 0.0}, {0.1, 0.0}, settings).agrees);
    CHECK_FALSE(compareEstimates({0.1 * (1 + 1e-3), 0.0}, {0.1, 0.0}, settings).agrees);
}

TEST_CASE("A planted 0.5 % bias fails the agreement test where it has the power",
          "[agreement][ttest]") {
    // The textured plane's whole image is where the CI matrix has the power for 0.5 %
    // (table in docs/design/figures.md): a light 0.5 % dimmer (what a light-selection
    // probability 0.5 % too large does to emitter sampling) must disagree, naming the
    // region; the scene as it is must agree.
    AgreementSettings settings;
    const AgreementScene scene = matrixScene("textured");
    const AgreementScene dimmer = planted(scene, R"(<color name="radiance" value="4"/>)",
                                          R"(<color name="radiance" value="3.98"/>)");
    const Estimator &pathMIS = scene.estimators[0];
    const auto reference = estimateRegions(scene, pathMIS, 0, settings);
    const auto same = estimateRegions(scene, pathMIS, 1, settings);
    const auto biased = estimateRegions(dimmer, pathMIS, 1, settings);
    const AgreementCell control = compareEstimates(same[0], reference[0], settings);
    const AgreementCell cell = compareEstimates(biased[0], reference[0], settings);
    INFO("same scene: " << control.z << " SE; light 0.5 % dimmer: " << cell.z
                        << " SE; detectable bias (%): " << 100 * cell.detectableBias);
    CHECK(control.agrees);
    CHECK(cell.powerful);
    CHECK_FALSE(cell.agrees);
}

TEST_CASE("A texture lookup shifted by half a texel fails the agreement test",
          "[agreement][ttest]") {
    // The albedo (a checkerboard darkening along u, 32 texels across the floor) read half
    // a texel off in u and v must disagree on the whole image and on the centre region.
    AgreementSettings settings;
    const AgreementScene scene = matrixScene("textured");
    const AgreementScene shifted = planted(
        scene, R"(<string name="filename" value="albedo.exr"/>)",
        R"(<string name="filename" value="albedo.exr"/><vector name="uvOffset" value="0.015625, 0.015625"/>)");
    const Estimator &pathMIS = scene.estimators[0];
    const auto reference = estimateRegions(scene, pathMIS, 0, settings);
    const auto biased = estimateRegions(shifted, pathMIS, 1, settings);
    REQUIRE(reference.size() == 2);
    for (size_t r = 0; r < reference.size(); ++r) {
        const AgreementCell cell = compareEstimates(biased[r], reference[r], settings);
        INFO((r == 0 ? "image" : scene.regions[0].name)
             << ": " << 100 * cell.difference << " % = " << cell.z << " SE");
        CHECK_FALSE(cell.agrees);
    }
}

TEST_CASE("A photon radius update that shrinks before counting fails the agreement test",
          "[agreement][ttest][photons]") {
    // The Cornell box's whole image, where the matrix's sppm column sees a bias of 1.45 %
    // with 95 % power (docs/design/figures.md): the planted slip above must disagree with
    // the reference there; the shipped photon mapper, the same seeds, must agree.
    const testing::TemporaryPlugin plugin(
        "planted_radius_update", NoriObject::EIntegrator,
        [](const PropertyList &props) { return std::make_shared<PlantedRadiusUpdate>(props); });
    AgreementSettings settings;
    const AgreementScene scene = matrixScene("cornell-box");
    const auto sppm = std::find_if(scene.estimators.begin(), scene.estimators.end(),
                                   [](const Estimator &e) { return e.label == "sppm"; });
    REQUIRE(sppm != scene.estimators.end());
    const int sppmIndex = static_cast<int>(sppm - scene.estimators.begin());
    Estimator slipped = *sppm;
    slipped.label = "planted_radius_update";
    slipped.integrator.replace(slipped.integrator.find("progressivephotonmapper"),
                               std::string("progressivephotonmapper").size(),
                               "planted_radius_update");
    const auto reference = estimateRegions(scene, scene.estimators[0], 0, settings);
    const auto shipped = estimateRegions(scene, *sppm, sppmIndex, settings);
    const auto biased = estimateRegions(scene, slipped, sppmIndex, settings);
    const AgreementCell control = compareEstimates(shipped[0], reference[0], settings);
    const AgreementCell cell = compareEstimates(biased[0], reference[0], settings);
    INFO("shipped sppm: " << 100 * control.difference << " % = " << control.z << " SE; planted: "
                          << 100 * cell.difference << " % = " << cell.z << " SE");
    std::cout << "Cornell box, image: shipped sppm " << 100 * control.difference << " % ("
              << control.z << " SE), planted radius update " << 100 * cell.difference << " % ("
              << cell.z << " SE)\n";
    CHECK(control.agrees);
    CHECK_FALSE(cell.agrees);
}
