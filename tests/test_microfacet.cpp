// Microfacet distributions against their definitions: D is normalised in projected area,
// ∫ D(m) cos θm dωm = 1, and Smith's G1 satisfies the projected-area identity
// cos θo = G1(ωo) ∫ ⟨ωo, m⟩⁺ D(m) dωm (Heitz 2014, "Understanding the Masking-Shadowing
// Function", eq. 43), integrated numerically, independently of the closed forms.
#include <nori/microfacet.h>
#include <nori/statistics.h>

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
    return 2.0 * M_PI * sum * h / 3.0;
}

/// cos θo / ∫ ⟨ωo, m⟩⁺ D(m) dωm: Smith's G1 from its definition.
double smithG1FromDefinition(const MicrofacetDistribution &distribution, double thetaO) {
    const Vector3f wo = direction(std::cos(thetaO), 0.0);
    const double integral = adaptiveSimpson2D(
        [&](double cosTheta, double phi) {
            const Vector3f m = direction(cosTheta, phi);
            return std::max(0.0f, wo.dot(m)) * static_cast<double>(distribution.D(m));
        },
        0.0, 0.0, 1.0, 2.0 * M_PI, 1e-9, 14);
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
                const double theta = degrees * M_PI / 180.0;
                const Vector3f wo = direction(std::cos(theta), 0.0);
                const double reference = smithG1FromDefinition(distribution, theta);
                INFO((type == Type::GGX ? "GGX" : "Beckmann")
                     << " alpha " << alpha << " at " << degrees << " degrees");
                CHECK(distribution.G1(wo, Vector3f(0, 0, 1)) ==
                      Approx(reference).margin(type == Type::GGX ? 1e-4 : 5e-3));
            }
    // Negative control: the G1 of a roughness 20% off is told apart at grazing angles.
    const double theta = 80.0 * M_PI / 180.0;
    const MicrofacetDistribution wrong(Type::GGX, 0.36f);
    CHECK(
        wrong.G1(direction(std::cos(theta), 0.0), Vector3f(0, 0, 1)) !=
        Approx(smithG1FromDefinition(MicrofacetDistribution(Type::GGX, 0.3f), theta)).margin(1e-2));
}
