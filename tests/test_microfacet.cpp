// Microfacet distributions against their definitions: D is normalised in projected area,
// ∫ D(m) cos θm dωm = 1, and Smith's G1 satisfies the projected-area identity
// cos θo = G1(ωo) ∫ ⟨ωo, m⟩⁺ D(m) dωm (Heitz 2014, "Understanding the Masking-Shadowing
// Function", eq. 43), integrated numerically, independently of the closed forms; the
// normal samplers (D cos θ, anisotropic, visible normals) pass χ² against their pdfs.
#include <nori/chisquare.h>
#include <nori/microfacet.h>
#include <nori/statistics.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace nori;

namespace {

using Type = MicrofacetDistribution::Type;

Vector3f direction(double cosTheta, double phi) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return Vector3f(static_cast<float>(sinTheta * std::cos(phi)),
                    static_cast<float>(sinTheta * std::sin(phi)), static_cast<float>(cosTheta));
}

/// ∫ D(m) cos θm dωm over the hemisphere, in (cos θ, φ) where dω = d(cos θ) dφ; D is
/// isotropic, so the φ integral is 2π. Composite Simpson on 2·10⁵ intervals of cos θ
/// resolves the sharpest lobe tested (α = 0.05: width ~α² = 2.5e-3 in cos θ).
double projectedArea(const std::function<double(const Vector3f &)> &D) {
    const int n = 200000;
    const double h = 1.0 / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double x = i * h;
        const double weight = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += weight * D(direction(x, 0.0)) * x;
    }
    return 2.0 * kPiDouble * sum * h / 3.0;
}

/// ∫ D(m) cos θm dωm over the hemisphere for any D, by adaptive Simpson in (cos θ, φ).
double projectedArea2D(const MicrofacetDistribution &distribution) {
    return adaptiveSimpson2D(
        [&](double cosTheta, double phi) {
            return cosTheta * static_cast<double>(distribution.D(direction(cosTheta, phi)));
        },
        0.0, 0.0, 1.0, 2.0 * kPiDouble, 1e-8, 16);
}

/// cos θo / ∫ ⟨ωo, m⟩⁺ D(m) dωm: Smith's G1 from its definition (ωo at azimuth phiO).
double smithG1FromDefinition(const MicrofacetDistribution &distribution, double thetaO,
                             double phiO = 0.0) {
    const Vector3f wo = direction(std::cos(thetaO), phiO);
    const double integral = adaptiveSimpson2D(
        [&](double cosTheta, double phi) {
            const Vector3f m = direction(cosTheta, phi);
            return std::max(0.0f, wo.dot(m)) * static_cast<double>(distribution.D(m));
        },
        0.0, 0.0, 1.0, 2.0 * kPiDouble, 1e-9, 14);
    return std::cos(thetaO) / integral;
}

} // namespace

TEST_CASE("Microfacet D integrates to 1 in projected area", "[microfacet]") {
    for (Type type : {Type::Beckmann, Type::GGX})
        for (float alpha : {0.05f, 0.2f, 0.6f, 1.0f}) {
            INFO((type == Type::GGX ? "GGX" : "Beckmann") << " alpha " << alpha);
            const MicrofacetDistribution distribution(type, alpha);
            CHECK(projectedArea([&](const Vector3f &m) { return distribution.D(m); }) ==
                  Approx(1.0).margin(2e-3));
        }
    // Negative control: GGX with cos³ where its definition has cos⁴ (a slip in
    // D = α²/(π cos⁴θ (α² + tan²θ)²)) is not normalised, and the integral says so.
    const MicrofacetDistribution ggx(Type::GGX, 0.3f);
    CHECK(projectedArea([&](const Vector3f &m) { return ggx.D(m) * m.z(); }) !=
          Approx(1.0).margin(2e-3));
}

TEST_CASE("Smith G1 matches its definition by projected area", "[microfacet]") {
    // GGX's G1 is exact; Beckmann's is Walter et al.'s rational approximation of the
    // erf form, accurate to ~4e-3 (Walter 2007, eq. 27).
    for (Type type : {Type::Beckmann, Type::GGX})
        for (float alpha : {0.1f, 0.3f, 0.7f})
            for (double degrees : {10.0, 45.0, 75.0, 85.0}) {
                const MicrofacetDistribution distribution(type, alpha);
                const double theta = degrees * kPiDouble / 180.0;
                const Vector3f wo = direction(std::cos(theta), 0.0);
                const double reference = smithG1FromDefinition(distribution, theta);
                INFO((type == Type::GGX ? "GGX" : "Beckmann")
                     << " alpha " << alpha << " at " << degrees << " degrees");
                CHECK(distribution.G1(wo, Vector3f(0, 0, 1)) ==
                      Approx(reference).margin(type == Type::GGX ? 1e-4 : 5e-3));
            }
    // Negative control: the G1 of a roughness 20% off is told apart at grazing angles.
    const double theta = 80.0 * kPiDouble / 180.0;
    const MicrofacetDistribution wrong(Type::GGX, 0.36f);
    CHECK(
        wrong.G1(direction(std::cos(theta), 0.0), Vector3f(0, 0, 1)) !=
        Approx(smithG1FromDefinition(MicrofacetDistribution(Type::GGX, 0.3f), theta)).margin(1e-2));
}

TEST_CASE("Anisotropic D integrates to 1 and its G1 matches the definition", "[microfacet]") {
    // The stretched distributions (Heitz 2014, §5.3): D by 2D adaptive quadrature, G1 in
    // azimuths between the two axes, where the projected roughness is neither αx nor αy.
    for (Type type : {Type::Beckmann, Type::GGX}) {
        const MicrofacetDistribution distribution(type, 0.15f, 0.6f);
        INFO((type == Type::GGX ? "GGX" : "Beckmann") << " alpha 0.15 x 0.6");
        CHECK(projectedArea2D(distribution) == Approx(1.0).margin(2e-3));
        for (double degrees : {30.0, 70.0, 85.0})
            for (double phi : {0.0, 0.6, 1.2, kPiDouble / 2}) {
                const double theta = degrees * kPiDouble / 180.0;
                INFO("wo at " << degrees << " degrees, azimuth " << phi);
                CHECK(distribution.G1(direction(std::cos(theta), phi), Vector3f(0, 0, 1)) ==
                      Approx(smithG1FromDefinition(distribution, theta, phi))
                          .margin(type == Type::GGX ? 1e-4 : 5e-3));
            }
    }
    // With αx = αy the anisotropic forms reduce to the isotropic warps' densities.
    const MicrofacetDistribution nearlyIsotropic(Type::GGX, 0.3f, 0.3000001f);
    const MicrofacetDistribution isotropic(Type::GGX, 0.3f);
    const Vector3f m = direction(0.8, 0.4);
    CHECK(nearlyIsotropic.D(m) == Approx(isotropic.D(m)).epsilon(1e-5));
    // Negative control: swapping the axes changes G1 where the azimuth is not symmetric.
    const MicrofacetDistribution swapped(Type::GGX, 0.6f, 0.15f);
    const double theta = 80.0 * kPiDouble / 180.0;
    CHECK(swapped.G1(direction(std::cos(theta), 0.3), Vector3f(0, 0, 1)) !=
          Approx(smithG1FromDefinition(MicrofacetDistribution(Type::GGX, 0.15f, 0.6f), theta, 0.3))
              .margin(1e-2));
}

namespace {

/// Normals drawn by sampleNormal(sample) or, when `from` is set, by sampleNormal(from, sample).
SamplingRoutine normalRoutine(const MicrofacetDistribution &distribution, const Vector3f *from) {
    SamplingRoutine routine;
    routine.sample = [distribution, from](const Point2f &u, Vector3f &m) {
        m = from ? distribution.sampleNormal(*from, u) : distribution.sampleNormal(u);
        return true;
    };
    routine.pdf = [distribution, from](const Vector3f &m) {
        return from ? distribution.pdfNormal(*from, m) : distribution.pdfNormal(m);
    };
    return routine;
}

ChiSquareResult normalChiSquare(const SamplingRoutine &routine, uint64_t seed, double level) {
    return nori::testing::chiSquare(routine, seed, level).result;
}

} // namespace

TEST_CASE("Microfacet normals are sampled from their densities, visible normals too",
          "[microfacet][chi2]") {
    // Lobes sharper than α ≈ 0.05 fall inside one histogram cell, where the quadrature of
    // the expected counts cannot resolve them; the Disney mirror-limit test covers those.
    const std::vector<MicrofacetDistribution> distributions = {
        {Type::GGX, 0.3f},        {Type::GGX, 0.1f, 0.5f},
        {Type::GGX, 0.8f, 0.05f}, {Type::Beckmann, 0.2f, 0.6f},
        {Type::GGX, 1.0f},        {Type::GGX, 0.05f, 0.2f}};
    const std::vector<Vector3f> views = {direction(1.0, 0.0), direction(0.7, 0.5),
                                         direction(0.1, 2.0), direction(0.02, 4.0)};
    const int tests = static_cast<int>(distributions.size() * (1 + views.size()));
    const double level = sidakCorrection(0.01, tests);
    uint64_t seed = 40;
    for (const MicrofacetDistribution &distribution : distributions) {
        INFO((distribution.type() == Type::GGX ? "GGX" : "Beckmann")
             << " alpha " << distribution.alphaX() << " x " << distribution.alphaY());
        const ChiSquareResult all =
            normalChiSquare(normalRoutine(distribution, nullptr), ++seed, level);
        INFO("D cos: " << all.message);
        CHECK(all.passed);
        for (const Vector3f &view : views) {
            const ChiSquareResult visible =
                normalChiSquare(normalRoutine(distribution, &view), ++seed, level);
            INFO("visible from cos " << view.z() << ": " << visible.message);
            CHECK(visible.passed);
        }
    }
    // Negative control: visible normals seen from one direction are not those seen from
    // another, and the test tells them apart.
    const MicrofacetDistribution ggx(Type::GGX, 0.5f, 0.2f);
    const Vector3f seen = direction(0.3, 0.0), claimed = direction(0.3, 1.0);
    SamplingRoutine wrong = normalRoutine(ggx, &seen);
    wrong.pdf = [ggx, claimed](const Vector3f &m) { return ggx.pdfNormal(claimed, m); };
    CHECK_FALSE(normalChiSquare(wrong, 7, 0.01).passed);
}
