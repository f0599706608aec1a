#include "testing/integratortest.h"

#include "testing/agreementscenes.h"
#include <nori/integrator.h>
#include <nori/object.h>
#include <nori/parser.h>
#include <nori/plugindoc.h>

#include <cmath>

namespace nori {

namespace {

/// The parameters both integrators get, for the quantities whose course integrators need
/// some: simple's point light (above the scenes' floor) and av's distance.
std::string quantityParameters(IntegratorQuantity quantity) {
    switch (quantity) {
    case IntegratorQuantity::PointLight:
        return R"(<point name="position" value="0.5, 2.5, 1"/><color name="energy" value="60, 60, 60"/>)";
    case IntegratorQuantity::AverageVisibility:
        return R"(<float name="length" value="0.6"/>)";
    default:
        return "";
    }
}

} // namespace

bool isIntegratorPlugin(const std::string &name) {
    for (NoriObject::EClassType kind : NoriObjectFactory::kindsOf(name))
        if (kind == NoriObject::EIntegrator)
            return true;
    return false;
}

PluginTestResult testIntegratorPlugin(const std::string &name, const PluginTestOptions &options) {
    const NoriObjectFactory::Entry &entry = NoriObjectFactory::entry(NoriObject::EIntegrator, name);
    PluginTestResult result;
    result.report = fmt::format("{} (integrator, {})\n", name, shortSourcePath(entry.sourceFile));
    AgreementSettings settings;
    settings.seed = options.seed;
    // An integrator that says it renders participating media is also compared with
    // volpath on a scene with media (Integrator::handlesMedia).
    bool withMedia = false, specularInView = true;
    // What it estimates decides what it is compared with (Integrator::quantity): found on
    // an instance made with no parameters, or, for the course names that need some, by
    // the name.
    IntegratorQuantity quantity = courseIntegratorQuantity(name);
    std::string parameters = quantityParameters(quantity);
    try {
        const auto integrator = std::static_pointer_cast<Integrator>(loadFromXMLString(
            fmt::format(R"(<integrator type="{}">{}</integrator>)", name, parameters)));
        quantity = integrator->quantity();
        parameters = quantityParameters(quantity);
        withMedia = integrator->handlesMedia();
        specularInView = integrator->rendersSpecularInView();
    } catch (const NoriException &error) {
        result.tested = true;
        result.passed = false;
        result.report += fmt::format("  cannot be created{}: {}\n",
                                     parameters.empty() ? " without parameters" : "", error.what());
        return result;
    }
    // Our integrator of that quantity, also when a user's file replaced it.
    const std::string reference = kBuiltinPrefix + std::string(referenceIntegrator(quantity));
    const bool radiance = quantity == IntegratorQuantity::Radiance;
    const std::vector<AgreementScene> scenes = integratorTestScenes(
        fmt::format(R"(<integrator type="{}">{}</integrator>)", name, parameters),
        withMedia && radiance, reference, parameters, !radiance);
    size_t comparisons = 0;
    for (const AgreementScene &scene : scenes) {
        if (scene.specularInView && !specularInView) {
            result.report += fmt::format("  {}: not compared: the camera sees mirrors or glass, "
                                         "which {} does not render (rendersSpecularInView)\n",
                                         scene.name, name);
            continue;
        }
        std::vector<RegionEstimate> reference, tested;
        try {
            reference = estimateRegions(scene, scene.estimators[0], 0, settings);
            tested = estimateRegions(scene, scene.estimators[1], 1, settings);
        } catch (const NoriException &error) {
            result.tested = true;
            result.passed = false;
            result.report += fmt::format("  {}: did not render: {}\n", scene.name, error.what());
            continue;
        }
        result.tested = true;
        for (size_t r = 0; r < reference.size(); ++r) {
            const AgreementCell cell = compareEstimates(tested[r], reference[r], settings);
            ++comparisons;
            result.passed &= cell.agrees;
            result.report += fmt::format(
                "  {:<22} {:<13} {} {:.5g} ± {:.2g}, {} {:.5g} ± {:.2g}: {:+.2f} % = "
                "{:+.2f} standard errors{}\n",
                scene.name, r == 0 ? "image" : scene.regions[r - 1].name, scene.estimators[0].label,
                reference[r].mean, reference[r].standardError, name, tested[r].mean,
                tested[r].standardError, 100.0 * cell.difference, cell.z,
                cell.agrees ? "" : "  DISAGREES");
        }
    }
    // With 16 batches each, the difference over its standard error follows Student's t
    // with about 30 degrees of freedom: beyond 4 with probability 4e-4, so that a correct
    // integrator fails one of ~20 comparisons with probability below 1 %.
    result.report += fmt::format(
        "  {} comparisons with {} ({} batches each, disagreement beyond {:g} standard "
        "errors)\n  verdict: {}\n",
        comparisons, withMedia && radiance ? "path_mis and volpath" : referenceIntegrator(quantity),
        settings.batches, settings.threshold, result.passed ? "pass" : "FAIL");
    return result;
}

} // namespace nori
