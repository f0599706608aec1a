// χ² tests of sharp microfacet lobes (Disney down to roughness 0.05, rough conductors
// down to α = 0.0025) in half-vector coordinates (src/testing/halfvectorroutine.h), where
// the sphere's histogram puts the whole lobe in one bin.
#include "testutil.h"

#include "testing/halfvectorroutine.h"

#include <nori/bsdf.h>
#include <nori/parser.h>
#include <nori/samplingroutines.h>

#include <catch2/catch.hpp>

#include <map>

using namespace nori;

namespace {

using Parameters = std::map<std::string, float>;

std::shared_ptr<BSDF> disney(const Parameters &parameters) {
    std::string xml = R"(<bsdf type="disney"><color name="baseColor" value="0.8, 0.5, 0.3"/>)";
    for (const auto &[name, value] : parameters)
        xml += fmt::format(R"(<float name="{}" value="{}"/>)", name, value);
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(xml + "</bsdf>"));
    REQUIRE(bsdf);
    return bsdf;
}

std::shared_ptr<BSDF> roughConductor(float alpha) {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(fmt::format(
        R"(<bsdf type="roughconductor"><float name="alpha" value="{}"/></bsdf>)", alpha)));
    REQUIRE(bsdf);
    return bsdf;
}

/// Incident direction at `degrees` from the normal, at an azimuth of 0.5 rad so that
/// anisotropic lobes are seen neither along their tangent nor across it.
Vector3f incident(float degrees) {
    return nori::testing::incidentDirection(degrees, 0.5f);
}

/// The χ² test in half-vector coordinates of width `alpha`: a 24 × 24 histogram and
/// 400,000 samples (about 700 a bin).
ChiSquareReport halfVectorChiSquare(const SamplingRoutine &routine, const Vector3f &wi,
                                    double alpha, uint64_t seed, double level) {
    ChiSquareOptions options;
    options.resolution = 24;
    options.sampleCount = 400000;
    options.seed = seed;
    options.significanceLevel = level;
    return runChiSquareTest(halfVectorRoutine(routine, wi, alpha), options);
}

const std::vector<float> kAngles = {0.0f, 30.0f, 60.0f, 85.0f};

/// The half-vector χ² of `bsdf` at every angle of kAngles, each a CHECK.
void checkSharpLobe(const BSDF &bsdf, double alpha, uint64_t &seed, double level) {
    for (const float angle : kAngles) {
        const Vector3f wi = incident(angle);
        const ChiSquareReport report =
            halfVectorChiSquare(bsdfRoutine(bsdf, wi), wi, alpha, ++seed, level);
        INFO(bsdf.toString() << " at " << angle << " degrees: " << report.result.message);
        CHECK(report.result.passed);
    }
}

} // namespace

TEST_CASE("Half-vector coordinates keep a density's integral", "[chi2]") {
    // The map's Jacobian: a rough conductor's pdf, integrated over the unit square by the
    // χ² test's own quadrature, is what it is over the sphere (the share of its lobe
    // above the surface), for a sharp and a broad lobe and both map widths.
    for (const float alpha : {0.0025f, 0.3f}) {
        auto bsdf = roughConductor(alpha);
        const Vector3f wi = incident(30.0f);
        for (const double mapAlpha : {0.0025, 0.3}) {
            const ChiSquareReport plane =
                halfVectorChiSquare(bsdfRoutine(*bsdf, wi), wi, mapAlpha, 7, 0.01);
            const ChiSquareReport sphere =
                nori::testing::chiSquare(bsdfRoutine(*bsdf, wi), 7, 0.01);
            INFO("alpha " << alpha << ", map " << mapAlpha << ": " << plane.pdfIntegral
                          << " against " << sphere.pdfIntegral);
            CHECK(plane.pdfIntegral == Approx(sphere.pdfIntegral).epsilon(2e-3));
        }
    }
}

TEST_CASE("Disney BSDF samples its pdf down to roughness 0.05", "[disney][chi2]") {
    // Roughness r gives α = r² (0.0025 at 0.05); the map's width is that α. Burley's
    // additive lobes (diffuse, sheen, clearcoat) fall in the square's broad half.
    const std::vector<Parameters> sets = {
        {{"metallic", 1}, {"roughness", 0.05f}},
        {{"metallic", 0}, {"roughness", 0.05f}, {"specular", 1}},
        {{"metallic", 0.5f}, {"roughness", 0.1f}, {"anisotropic", 0.6f}},
        {{"metallic", 0}, {"roughness", 0.15f}, {"clearcoat", 1}, {"clearcoatGloss", 0.9f}},
        {{"metallic", 1}, {"roughness", 0.05f}, {"sheen", 1}, {"clearcoat", 0.5f}}};
    const double level = sidakCorrection(0.01, static_cast<int>(sets.size() * kAngles.size()));
    uint64_t seed = 500;
    for (const Parameters &parameters : sets) {
        auto bsdf = disney(parameters);
        const double alpha = std::max(0.001, std::pow(double(parameters.at("roughness")), 2.0));
        checkSharpLobe(*bsdf, alpha, seed, level);
    }
}

TEST_CASE("Sharp-lobe χ² rejects a pdf 10 % too wide that the sphere's histogram misses",
          "[disney][chi2]") {
    // Negative control: samples of roughness 0.05 against the pdf of roughness 0.0524
    // (α 10 % larger), at 30° and 60°: the sphere's histogram passes it (the lobe lies
    // inside one of its bins), half-vector coordinates reject it. (At normal incidence the
    // lobe sits on the sphere's pole, where its bins are narrower, and both reject it.)
    auto sharp = disney({{"metallic", 1}, {"roughness", 0.05f}});
    auto wider = disney({{"metallic", 1}, {"roughness", 0.05244f}});
    for (const float angle : {30.0f, 60.0f}) {
        const Vector3f wi = incident(angle);
        SamplingRoutine routine = bsdfRoutine(*sharp, wi);
        routine.pdf = bsdfRoutine(*wider, wi).pdf;
        const ChiSquareReport plane = halfVectorChiSquare(routine, wi, 0.0025, 77, 0.01);
        const ChiSquareReport sphere = nori::testing::chiSquare(routine, 77, 0.01);
        INFO("at " << angle << " degrees: half-vector " << plane.result.message << "; sphere "
                   << sphere.result.message);
        CHECK_FALSE(plane.result.passed);
        CHECK(sphere.result.passed);
    }
}

TEST_CASE("Rough conductors sample their pdf down to alpha 0.0025", "[chi2]") {
    const std::vector<float> alphas = {0.0025f, 0.01f, 0.05f};
    const double level = sidakCorrection(0.01, static_cast<int>(alphas.size() * kAngles.size()));
    uint64_t seed = 600;
    for (const float alpha : alphas)
        checkSharpLobe(*roughConductor(alpha), alpha, seed, level);
}
