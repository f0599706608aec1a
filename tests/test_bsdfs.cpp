// BSDFs: χ² tests of every glossy/diffuse BSDF at several angles (grazing, and from
// inside for dielectrics), the laws of the specular ones, Fresnel values, energy
// conservation, and a negative control for each kind of lobe.
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/samplingroutines.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <complex>

#include <iostream>

using namespace nori;
using Catch::Contains;
using nori::testing::chiSquare;
using nori::testing::errorOf;

namespace {

std::shared_ptr<BSDF> makeBSDF(const std::string &xml) {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(xml));
    REQUIRE(bsdf);
    return bsdf;
}

/// Incident direction at `degrees` from the normal (beyond 90: from inside), azimuth 0.
Vector3f incident(float degrees) {
    return nori::testing::incidentDirection(degrees);
}

/// Mean and standard error of the sampled weight (luminance), with refracted weights
/// multiplied by eta² to undo radiance scaling: the fraction of energy scattered.
std::pair<double, double> albedo(const BSDF &bsdf, const Vector3f &wi, int n = 200000) {
    PCG32 random(5, 6);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
        BSDFQueryRecord bRec(wi);
        const float u = random.nextFloat();
        double value = bsdf.sample(bRec, Point2f(u, random.nextFloat())).getLuminance();
        value *= static_cast<double>(bRec.eta) * bRec.eta;
        sum += value;
        sum2 += value * value;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

const std::vector<std::string> kGlossyBSDFs = {
    R"(<bsdf type="diffuse"/>)",
    R"(<bsdf type="microfacet"><float name="alpha" value="0.1"/></bsdf>)",
    R"(<bsdf type="microfacet"><float name="alpha" value="0.4"/><color name="kd" value="0.2"/></bsdf>)",
    R"(<bsdf type="roughconductor"><string name="distribution" value="beckmann"/><float name="alpha" value="0.15"/></bsdf>)",
    R"(<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.5"/><string name="material" value="Au"/></bsdf>)",
    R"(<bsdf type="roughdielectric"><string name="distribution" value="beckmann"/><float name="alpha" value="0.2"/></bsdf>)",
    R"(<bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.6"/><float name="intIOR" value="1.33"/></bsdf>)",
    // Anisotropic, and roughness remapped as pbrt-v4 does (α = √r).
    R"(<bsdf type="roughconductor"><float name="alphaU" value="0.08"/><float name="alphaV" value="0.5"/></bsdf>)",
    R"(<bsdf type="roughconductor"><string name="distribution" value="beckmann"/><float name="alphaU" value="0.4"/><float name="alphaV" value="0.1"/></bsdf>)",
    R"(<bsdf type="roughdielectric"><float name="alphaU" value="0.3"/><float name="alphaV" value="0.05"/><boolean name="remapRoughness" value="true"/></bsdf>)",
};

} // namespace

TEST_CASE("Every non-specular BSDF samples its pdf, at grazing angles and from inside",
          "[bsdf][chi2]") {
    const std::vector<float> outside = {0.0f, 40.0f, 75.0f, 89.0f};
    const std::vector<float> inside = {110.0f, 150.0f, 180.0f};
    int tests = 0;
    for (const std::string &xml : kGlossyBSDFs)
        tests += static_cast<int>(
            outside.size() + (xml.find("dielectric") != std::string::npos ? inside.size() : 0));
    const double alpha = sidakCorrection(0.01, tests);
    uint64_t seed = 100;
    for (const std::string &xml : kGlossyBSDFs) {
        auto bsdf = makeBSDF(xml);
        std::vector<float> angles = outside;
        if (xml.find("dielectric") != std::string::npos)
            angles.insert(angles.end(), inside.begin(), inside.end());
        // Anisotropic lobes are seen from off their axes.
        const float azimuth = xml.find("alphaU") != std::string::npos ? 0.6f : 0.0f;
        for (float angle : angles) {
            const ChiSquareReport report =
                chiSquare(bsdfRoutine(*bsdf, nori::testing::incidentDirection(angle, azimuth)),
                          ++seed, alpha);
            INFO(bsdf->toString() << " at " << angle << " degrees: " << report.result.message);
            CHECK(report.result.passed);
        }
    }
}

TEST_CASE("No BSDF scatters more energy than arrives", "[bsdf][energy]") {
    std::vector<std::string> all = kGlossyBSDFs;
    all.push_back(R"(<bsdf type="mirror"/>)");
    all.push_back(R"(<bsdf type="dielectric"/>)");
    all.push_back(R"(<bsdf type="conductor"><string name="material" value="Ag"/></bsdf>)");
    all.push_back(
        R"(<bsdf type="roughconductor"><float name="alpha" value="1.0"/><color name="eta" value="0.2"/><color name="k" value="10"/></bsdf>)");
    for (const std::string &xml : all) {
        auto bsdf = makeBSDF(xml);
        for (float angle : {0.0f, 45.0f, 80.0f, 89.5f, 120.0f, 175.0f}) {
            const auto [mean, error] = albedo(*bsdf, incident(angle));
            INFO(bsdf->toString() << " at " << angle << ": albedo " << mean << " ± " << error);
            // The estimate may exceed 1 only by its own noise (4 standard errors).
            CHECK(mean <= 1.0 + 4.0 * error + 1e-6);
        }
    }
    // The check has the power to catch a BSDF that creates 3% energy: a perfect
    // mirror's albedo is exactly 1 with zero variance, and 1.03 > 1 + 4·0.
    const auto [mirror, mirrorError] = albedo(*makeBSDF(R"(<bsdf type="mirror"/>)"), incident(30));
    CHECK(mirror == Approx(1.0));
    CHECK_FALSE(1.03 * mirror <= 1.0 + 4.0 * mirrorError + 1e-6);
}

TEST_CASE("Fresnel reflectance matches closed forms", "[bsdf][fresnel]") {
    // Normal incidence: ((η − 1)/(η + 1))² for dielectrics, ((η−1)² + k²)/((η+1)² + k²)
    // for conductors.
    CHECK(fresnelDielectric(1.0f, 1.0f, 1.5f) == Approx(0.04f).epsilon(1e-5));
    CHECK(fresnelDielectric(-1.0f, 1.0f, 1.5f) == Approx(0.04f).epsilon(1e-5));
    CHECK(fresnelDielectric(0.0f, 1.0f, 1.5f) == Approx(1.0f));
    // Total internal reflection beyond the critical angle asin(1/1.5) ≈ 41.8° inside.
    CHECK(fresnelDielectric(-std::cos(degToRad(45.0f)), 1.0f, 1.5f) == 1.0f);
    CHECK(fresnelDielectric(-std::cos(degToRad(40.0f)), 1.0f, 1.5f) < 1.0f);
    const Color3f f = fresnelConductor(1.0f, Color3f(0.2f, 1.0f, 1.5f), Color3f(3.0f, 0.0f, 1.0f));
    CHECK(f.r() == Approx((0.64f + 9.0f) / (1.44f + 9.0f)).epsilon(1e-5));
    CHECK(f.g() == Approx(0.0f).margin(1e-6));
    CHECK(f.b() == Approx((0.25f + 1.0f) / (6.25f + 1.0f)).epsilon(1e-5));
    // At every angle, the complex form of r⊥ and r∥ (PBR 4th ed. §9.3.6), for gold, a
    // dielectric-like η with small k, and the normal-incidence case's values.
    const auto complexForm = [](float cosThetaI, float eta, float k) {
        using Complex = std::complex<double>;
        const Complex etaC(eta, k);
        const double sin2ThetaI = 1.0 - double(cosThetaI) * cosThetaI;
        const Complex cosThetaT = std::sqrt(1.0 - sin2ThetaI / (etaC * etaC));
        const Complex rPerp =
            (double(cosThetaI) - etaC * cosThetaT) / (double(cosThetaI) + etaC * cosThetaT);
        const Complex rPar =
            (etaC * double(cosThetaI) - cosThetaT) / (etaC * double(cosThetaI) + cosThetaT);
        return 0.5 * (std::norm(rPerp) + std::norm(rPar));
    };
    const Color3f etas(0.143119f, 1.5f, 0.2f), ks(3.98316f, 0.01f, 3.0f);
    for (int step = 0; step <= 90; ++step) {
        const float cosThetaI = std::cos(degToRad(float(step)));
        const Color3f real = fresnelConductor(cosThetaI, etas, ks);
        for (int c = 0; c < 3; ++c) {
            CAPTURE(step, c);
            CHECK(real[c] == Approx(complexForm(cosThetaI, etas[c], ks[c])).margin(1e-5));
        }
    }
    CHECK_THAT(errorOf([] {
                   Color3f eta, k;
                   lookupConductor("Gold", eta, k);
               }),
               Contains("unknown metal 'Gold'"));
}

TEST_CASE("Specular BSDFs obey the laws of reflection and refraction", "[bsdf][specular]") {
    const Vector3f wi = incident(35.0f);
    BSDFQueryRecord mirrorRec(wi);
    CHECK((makeBSDF(R"(<bsdf type="mirror"/>)")->sample(mirrorRec, Point2f(0.3f, 0.7f)) ==
           Color3f(1.0f))
              .all());
    CHECK(mirrorRec.measure == EDiscrete);
    CHECK(mirrorRec.wo.isApprox(Vector3f(-wi.x(), -wi.y(), wi.z())));

    auto conductor =
        makeBSDF(R"(<bsdf type="conductor"><string name="material" value="Au"/></bsdf>)");
    BSDFQueryRecord conductorRec(wi);
    Color3f eta, k;
    lookupConductor("Au", eta, k);
    CHECK(conductor->sample(conductorRec, Point2f(0.5f, 0.5f))
              .isApprox(fresnelConductor(wi.z(), eta / 1.000277f, k / 1.000277f), 1e-5f));

    // Dielectric: refraction obeys Snell's law, reflection is chosen with probability F,
    // and beyond the critical angle from inside everything reflects.
    auto glass = makeBSDF(
        R"(<bsdf type="dielectric"><float name="intIOR" value="1.5"/><float name="extIOR" value="1"/></bsdf>)");
    const float fresnel = fresnelDielectric(wi.z(), 1.0f, 1.5f);
    PCG32 random(1, 1);
    const int n = 100000;
    int reflected = 0;
    for (int i = 0; i < n; ++i) {
        BSDFQueryRecord bRec(wi);
        const float u = random.nextFloat();
        const Color3f weight = glass->sample(bRec, Point2f(u, random.nextFloat()));
        if (bRec.wo.z() > 0.0f) {
            ++reflected;
            CHECK(weight.isApprox(Color3f(1.0f)));
        } else {
            // sin θt · 1.5 = sin θi · 1, and radiance is scaled by (1/1.5)².
            CHECK(1.5f * Frame::sinTheta(bRec.wo) == Approx(Frame::sinTheta(wi)).epsilon(1e-4));
            CHECK(weight.isApprox(Color3f(1.0f / 2.25f), 1e-5f));
        }
    }
    // Binomial: the reflected count lies within 5 standard deviations of n·F.
    const double sigma = std::sqrt(n * fresnel * (1.0 - fresnel));
    CHECK(std::abs(reflected - n * fresnel) < 5.0 * sigma);
    // Negative control (discrete lobe): the same count tested against F of water (1.33)
    // is rejected.
    const float wrongF = fresnelDielectric(wi.z(), 1.0f, 1.33f);
    const double wrongSigma = std::sqrt(n * wrongF * (1.0 - wrongF));
    std::cout << fmt::format("negative control 'dielectric reflection count against F of "
                             "water': z = {:.1f}\n",
                             (reflected - n * wrongF) / wrongSigma);
    CHECK(std::abs(reflected - n * wrongF) > 5.0 * wrongSigma);

    BSDFQueryRecord trapped(incident(180.0f - 50.0f));
    CHECK(glass->sample(trapped, Point2f(0.999f, 0.5f)).isApprox(Color3f(1.0f)));
    CHECK(trapped.wo.z() < 0.0f); // reflected back inside
}

TEST_CASE("Smooth glass lists the lobes it samples, with their probabilities and weights",
          "[bsdf][specular]") {
    // discreteLobes() must describe sample() exactly: a sample whose first number falls in
    // a lobe's share of [0, 1) returns that lobe's direction and eta, and the weight the
    // lobe lists divided by its probability. Over 2,000 directions on the sphere (from
    // outside, from inside, beyond the critical angle).
    auto glass = makeBSDF(
        R"(<bsdf type="dielectric"><float name="intIOR" value="1.5"/><float name="extIOR" value="1"/></bsdf>)");
    PCG32 random(9, 4);
    int totalReflections = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vector3f wi = nori::testing::randomDirection(random);
        if (std::abs(wi.z()) < 1e-3f)
            continue; // grazing: the refracted direction is ill-conditioned
        DiscreteLobe lobes[BSDF::kMaxDiscreteLobes];
        const int count = glass->discreteLobes(BSDFQueryRecord(wi), lobes);
        REQUIRE((count == 1 || count == 2));
        float start = 0.0f, total = 0.0f;
        for (int l = 0; l < count; ++l) {
            const DiscreteLobe &lobe = lobes[l];
            INFO("wi " << wi.transpose() << ", lobe " << l << " of " << count);
            REQUIRE(lobe.probability > 0.0f);
            BSDFQueryRecord bRec(wi);
            const Color3f weight =
                glass->sample(bRec, Point2f(start + 0.5f * lobe.probability, 0.5f));
            CHECK(bRec.wo.isApprox(lobe.wo, 1e-5f));
            CHECK(bRec.eta == Approx(lobe.eta).epsilon(1e-6));
            CHECK((weight * lobe.probability).isApprox(lobe.weight, 1e-5f));
            start += lobe.probability;
            total += lobe.probability;
        }
        CHECK(total == Approx(1.0f).epsilon(1e-6));
        totalReflections += count == 1;
    }
    CHECK(totalReflections > 0); // total internal reflection was among the directions
    // BSDFs with a continuous part, and single-lobe ones, list nothing: they are sampled.
    DiscreteLobe lobes[BSDF::kMaxDiscreteLobes];
    CHECK(makeBSDF(R"(<bsdf type="diffuse"/>)")->discreteLobes(incident(30.0f), lobes) == 0);
    CHECK(makeBSDF(R"(<bsdf type="roughdielectric"/>)")->discreteLobes(incident(30.0f), lobes) ==
          0);
}

TEST_CASE("Negative controls: χ² rejects a wrong glossy lobe and a wrong transmission lobe",
          "[bsdf][negative]") {
    // Glossy reflection: samples of α = 0.3 against the pdf of α = 0.36.
    auto sampler =
        makeBSDF(R"(<bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>)");
    auto wrongPdf =
        makeBSDF(R"(<bsdf type="roughconductor"><float name="alpha" value="0.36"/></bsdf>)");
    SamplingRoutine glossy = bsdfRoutine(*sampler, incident(30.0f));
    glossy.pdf = bsdfRoutine(*wrongPdf, incident(30.0f)).pdf;
    const ChiSquareReport glossyReport = chiSquare(glossy, 3, 0.01);
    std::cout << fmt::format("negative control 'roughconductor alpha 0.3 against pdf of 0.36': "
                             "p-value {:.3g}\n",
                             glossyReport.result.pValue);
    CHECK_FALSE(glossyReport.result.passed);

    // Transmission: glass of 1.5 against the pdf of 1.4 (the refracted lobe moves).
    auto glass = makeBSDF(
        R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/><float name="intIOR" value="1.5"/></bsdf>)");
    auto other = makeBSDF(
        R"(<bsdf type="roughdielectric"><float name="alpha" value="0.2"/><float name="intIOR" value="1.4"/></bsdf>)");
    SamplingRoutine transmission = bsdfRoutine(*glass, incident(20.0f));
    transmission.pdf = bsdfRoutine(*other, incident(20.0f)).pdf;
    const ChiSquareReport transmissionReport = chiSquare(transmission, 4, 0.01);
    std::cout << fmt::format("negative control 'roughdielectric IOR 1.5 against pdf of 1.4': "
                             "p-value {:.3g}\n",
                             transmissionReport.result.pValue);
    CHECK_FALSE(transmissionReport.result.passed);

    // Anisotropy: samples of (αu, αv) = (0.08, 0.5) against the pdf of the axes swapped.
    auto anisotropic = makeBSDF(
        R"(<bsdf type="roughconductor"><float name="alphaU" value="0.08"/><float name="alphaV" value="0.5"/></bsdf>)");
    auto swapped = makeBSDF(
        R"(<bsdf type="roughconductor"><float name="alphaU" value="0.5"/><float name="alphaV" value="0.08"/></bsdf>)");
    SamplingRoutine stretched =
        bsdfRoutine(*anisotropic, nori::testing::incidentDirection(30.0f, 0.7f));
    stretched.pdf = bsdfRoutine(*swapped, nori::testing::incidentDirection(30.0f, 0.7f)).pdf;
    const ChiSquareReport stretchedReport = chiSquare(stretched, 5, 0.01);
    std::cout << fmt::format("negative control 'roughconductor alphaU/alphaV against the axes "
                             "swapped': p-value {:.3g}\n",
                             stretchedReport.result.pValue);
    CHECK_FALSE(stretchedReport.result.passed);
}

TEST_CASE("BSDF parameters are validated", "[bsdf]") {
    CHECK_THAT(errorOf([] {
                   makeBSDF(
                       R"(<bsdf type="roughconductor"><float name="alpha" value="-0.1"/></bsdf>)");
               }),
               Contains("'alpha' must be positive"));
    CHECK_THAT(errorOf([] {
                   makeBSDF(R"(<bsdf type="roughconductor"><float name="alphaU" value="0.2"/>
                       <float name="alphaV" value="0"/></bsdf>)");
               }),
               Contains("'alphaV' must be positive"));
    CHECK_THAT(errorOf([] {
                   makeBSDF(R"(<bsdf type="roughconductor"><float name="alphaU" value="0.2"/>
                       <float name="alpha" value="0.1"/></bsdf>)");
               }),
               Contains("give 'alpha', or 'alphaU' and 'alphaV', not both"));
    CHECK_THAT(
        errorOf([] {
            makeBSDF(
                R"(<bsdf type="roughdielectric"><string name="distribution" value="phong"/></bsdf>)");
        }),
        Contains("unknown microfacet distribution 'phong'"));
    CHECK_THAT(
        errorOf([] {
            makeBSDF(
                R"(<bsdf type="conductor"><string name="material" value="Au"/><color name="eta" value="1"/></bsdf>)");
        }),
        Contains("either 'material' or 'eta' and 'k'"));
    CHECK_THAT(errorOf([] {
                   makeBSDF(R"(<bsdf type="microfacet"><color name="kd" value="1.5"/></bsdf>)");
               }),
               Contains("'kd' must lie in [0, 1]"));
}
