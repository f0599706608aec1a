// The BSDFs of real scenes (Mitsuba's plastic, roughplastic, twosided, thindielectric,
// blendbsdf; pbrt-v4's diffusetransmission and mix): their albedo against an independent
// integration of eval(), a planted wrong pdf that their χ² test must reject, and the
// properties each model promises. (The automatic plugin test runs their χ², reciprocity
// and white-furnace checks on every example of their doc comments.)
#include "testutil.h"

#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/render.h>
#include <nori/samplingroutines.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

std::shared_ptr<BSDF> makeBSDF(const std::string &xml) {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(xml));
    REQUIRE(bsdf);
    return bsdf;
}

/// ∫ f(wi, wo) |cos θo| dωo over the whole sphere by the midpoint rule on an n × 2n grid in
/// (cos θo, φo), in double precision.
double integrateEval(const BSDF &bsdf, const Vector3f &wi, int n) {
    double sum = 0.0;
    for (int i = 0; i < 2 * n; ++i) {
        const double mu = -1.0 + (i + 0.5) / n;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        for (int j = 0; j < 2 * n; ++j) {
            const double phi = 2.0 * kPiDouble * (j + 0.5) / (2 * n);
            const Vector3f wo(static_cast<float>(sinTheta * std::cos(phi)),
                              static_cast<float>(sinTheta * std::sin(phi)), static_cast<float>(mu));
            const BSDFQueryRecord bRec(wi, wo, ESolidAngle);
            sum += bsdf.eval(bRec).getLuminance() * std::abs(mu);
        }
    }
    // Each cell covers (1/n in μ) × (π/n in φ).
    return sum * (1.0 / n) * (kPiDouble / n);
}

double standardError(const RunningMoments &moments) {
    return std::sqrt(moments.variance() / static_cast<double>(moments.count));
}

/// The luminance of sample()'s weights for wi: their mean and its standard error, split
/// into the part carried by Dirac lobes and the rest.
struct SampledAlbedo {
    RunningMoments all, discrete;
};
SampledAlbedo sampleAlbedo(const BSDF &bsdf, const Vector3f &wi, int count, uint64_t seed) {
    PCG32 random(seed, 1);
    SampledAlbedo result;
    for (int i = 0; i < count; ++i) {
        BSDFQueryRecord bRec(wi);
        const float u = random.nextFloat();
        const Color3f weight = bsdf.sample(bRec, Point2f(u, random.nextFloat()));
        const double value = weight.getLuminance();
        result.all.add(value);
        result.discrete.add(bRec.measure == EDiscrete ? value : 0.0);
    }
    return result;
}

/// The same routine with its pdf asked for the direction rotated by 0.3 rad about +x: a
/// density that still integrates to 1 over the sphere but is in the wrong place, as a
/// pdf() with a slipped coordinate would be.
SamplingRoutine withRotatedPdf(SamplingRoutine routine) {
    const Eigen::Matrix3f rotation =
        Eigen::AngleAxisf(0.3f, Eigen::Vector3f::UnitX()).toRotationMatrix();
    auto pdf = routine.pdf;
    routine.pdf = [pdf, rotation](const Vector3f &point) {
        return pdf(Vector3f(rotation * point));
    };
    return routine;
}

const char *const kPlastic =
    R"(<bsdf type="plastic"><color name="diffuseReflectance" value="0.1, 0.3, 0.6"/></bsdf>)";
const char *const kPlasticNonlinear = R"(<bsdf type="plastic"><string name="intIOR" value="bk7"/>
    <boolean name="nonlinear" value="true"/><color name="diffuseReflectance" value="0.8"/></bsdf>)";
const char *const kRoughPlastic = R"(<bsdf type="roughplastic"><float name="alpha" value="0.2"/>
    <color name="diffuseReflectance" value="0.7, 0.3, 0.1"/></bsdf>)";
const char *const kRoughPlasticGGX = R"(<bsdf type="roughplastic">
    <string name="distribution" value="ggx"/><float name="alpha" value="0.4"/>
    <float name="intIOR" value="1.7"/><color name="diffuseReflectance" value="0.9"/></bsdf>)";
const char *const kRoughPlasticAnisotropic = R"(<bsdf type="roughplastic">
    <string name="distribution" value="ggx"/><float name="alphaU" value="0.1"/>
    <float name="alphaV" value="0.4"/><color name="diffuseReflectance" value="0.5"/></bsdf>)";
const char *const kDiffuseTransmission = R"(<bsdf type="diffusetransmission">
    <color name="reflectance" value="0.3, 0.5, 0.2"/>
    <color name="transmittance" value="0.5, 0.4, 0.1"/></bsdf>)";
const char *const kBlend = R"(<bsdf type="blendbsdf"><float name="weight" value="0.3"/>
    <bsdf type="diffuse"><color name="albedo" value="0.8, 0.2, 0.2"/></bsdf>
    <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></bsdf>)";
const char *const kBlendWithGlass = R"(<bsdf type="blendbsdf"><float name="weight" value="0.6"/>
    <bsdf type="dielectric"/><bsdf type="diffuse"/></bsdf>)";
const char *const kTwoSided = R"(<bsdf type="twosided">
    <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>
    <bsdf type="diffuse"><color name="albedo" value="0.2, 0.5, 0.2"/></bsdf></bsdf>)";

} // namespace

TEST_CASE("The Fresnel diffuse reflectance agrees with d'Eon and Irving's fit", "[materials]") {
    // The fit of d'Eon and Irving 2011 (eq. 5 of their supplement; max. relative error 0.1 %
    // for η in [1, 2]), as Mitsuba writes it.
    auto fit = [](double eta) {
        const double i = 1.0 / eta;
        return 0.919317 - 3.4793 * i + 6.75335 * i * i - 7.80989 * i * i * i +
               4.98554 * i * i * i * i - 1.36881 * i * i * i * i * i;
    };
    for (const float eta : {1.1f, 1.33f, 1.49f, 1.5046f, 1.8f}) {
        INFO("eta = " << eta);
        CHECK(fresnelDiffuseReflectance(eta) == Approx(fit(eta)).epsilon(2e-3));
        // Reciprocity of the interface: (1/η²)(1 − F_dr(η)) = 1 − F_dr(1/η).
        CHECK((1.0 - fresnelDiffuseReflectance(eta)) / (eta * eta) ==
              Approx(1.0 - fresnelDiffuseReflectance(1.0f / eta)).epsilon(1e-5));
    }
    CHECK(lookupIOR("polypropylene") == 1.49f);
    CHECK(lookupIOR("BK7") == 1.5046f);
    CHECK_THAT(errorOf([] { lookupIOR("watr"); }), Catch::Contains("did you mean 'water'"));
}

TEST_CASE("Each new BSDF's albedo agrees with an independent integration of its eval()",
          "[materials][statistical]") {
    // sample()'s mean weight (10⁶ samples, fixed seeds) against Dirac lobes' share plus a
    // quadrature of eval()·|cos θo| over the sphere, within 4 standard errors and the
    // quadrature's own error (the change from a 512- to a 1024-row grid, twice).
    for (const char *xml :
         {kPlastic, kPlasticNonlinear, kRoughPlastic, kRoughPlasticGGX, kRoughPlasticAnisotropic,
          kDiffuseTransmission, kBlend, kBlendWithGlass, kTwoSided}) {
        const auto bsdf = makeBSDF(xml);
        for (const float degrees : {10.0f, 45.0f, 75.0f, 120.0f}) {
            const Vector3f wi = incidentDirection(degrees, 0.4f);
            const SampledAlbedo sampled = sampleAlbedo(*bsdf, wi, 1000000, 17);
            const double coarse = integrateEval(*bsdf, wi, 512);
            const double fine = integrateEval(*bsdf, wi, 1024);
            const double expected = sampled.discrete.mean + fine;
            // (+ 1e-6 of the value: the float rounding of weights that do not vary at all.)
            const double tolerance =
                4.0 * standardError(sampled.all) + 2.0 * std::abs(fine - coarse) + 1e-6 * expected;
            INFO(bsdf->toString() << " at " << degrees << "°: sampled " << sampled.all.mean << " ± "
                                  << standardError(sampled.all) << ", Dirac lobes "
                                  << sampled.discrete.mean << " + quadrature " << fine
                                  << " (coarse " << coarse << ")");
            CHECK(std::abs(sampled.all.mean - expected) <= tolerance);
            // What the model promises: no more light leaves than arrives.
            CHECK(sampled.all.mean <= 1.0 + 4.0 * standardError(sampled.all));
            // The albedo() the AOV reads agrees too (its own 8 × 8 grid where it has no
            // closed form, so only roughly).
            const double albedo = bsdf->albedo(BSDFQueryRecord(wi)).getLuminance();
            CHECK(albedo == Approx(sampled.all.mean).margin(0.05));
        }
    }
}

TEST_CASE("Plastic's closed-form albedo is F·s + ρ'(1 − F)(1 − F_dr)/η²", "[materials]") {
    // The sample mean of the smooth model, exactly (its Dirac part carries F exactly).
    for (const char *xml : {kPlastic, kPlasticNonlinear}) {
        const auto bsdf = makeBSDF(xml);
        for (const float degrees : {0.0f, 30.0f, 60.0f, 85.0f}) {
            const Vector3f wi = incidentDirection(degrees);
            const SampledAlbedo sampled = sampleAlbedo(*bsdf, wi, 400000, 5);
            INFO(xml << " at " << degrees << "°");
            CHECK(std::abs(bsdf->albedo(BSDFQueryRecord(wi)).getLuminance() - sampled.all.mean) <=
                  4.0 * standardError(sampled.all));
        }
    }
}

TEST_CASE("A planted wrong pdf fails the χ² test of each new BSDF", "[materials][chi2]") {
    // The negative control of the automatic χ² test, per BSDF: the same sampler against
    // its pdf asked at a rotated direction must be rejected, the true pdf accepted.
    // (thindielectric has no density to get wrong: all its lobes are Dirac's.)
    const double level = sidakCorrection(0.01, 2 * 9);
    uint64_t seed = 1;
    for (const char *xml : {kPlastic, kRoughPlastic, kRoughPlasticAnisotropic, kDiffuseTransmission,
                            kBlend, kTwoSided,
                            R"(<bsdf type="mix"><float name="amount" value="0.5"/>
                                 <bsdf type="diffuse"/><bsdf type="roughplastic"/></bsdf>)",
                            kBlendWithGlass, kPlasticNonlinear}) {
        const auto bsdf = makeBSDF(xml);
        const Vector3f wi = incidentDirection(xml == kTwoSided ? 140.0f : 40.0f, 0.3f);
        const SamplingRoutine routine = bsdfRoutine(*bsdf, wi);
        INFO(bsdf->toString());
        CHECK(chiSquare(routine, seed++, level).result.passed);
        CHECK_FALSE(chiSquare(withRotatedPdf(routine), seed++, level).result.passed);
    }
}

TEST_CASE("twosided reflects from behind as its nested BSDF does from the front", "[materials]") {
    const auto single = makeBSDF(R"(<bsdf type="twosided"><bsdf type="roughconductor">
        <float name="alpha" value="0.3"/></bsdf></bsdf>)");
    const auto inner =
        makeBSDF(R"(<bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>)");
    PCG32 random(9, 1);
    for (int i = 0; i < 100; ++i) {
        const Vector3f wi = randomDirection(random), wo = randomDirection(random);
        const Vector3f wiUp(wi.x(), wi.y(), std::abs(wi.z())),
            woUp(wo.x(), wo.y(), wi.z() < 0 ? -wo.z() : wo.z());
        const BSDFQueryRecord query(wi, wo, ESolidAngle), mirrored(wiUp, woUp, ESolidAngle);
        CHECK((single->eval(query) - inner->eval(mirrored)).abs().maxCoeff() <= 1e-6f);
        CHECK(single->pdf(query) == Approx(inner->pdf(mirrored)).margin(1e-6));
    }
    // The back of the two-sided pair is the second BSDF.
    const auto pair = makeBSDF(kTwoSided);
    const BSDFQueryRecord back(incidentDirection(150.0f), incidentDirection(130.0f, 2.0f),
                               ESolidAngle);
    CHECK(pair->eval(back).isApprox(Color3f(0.2f, 0.5f, 0.2f) * kInvPi));
    CHECK_THAT(
        errorOf([] { makeBSDF(R"(<bsdf type="twosided"><bsdf type="dielectric"/></bsdf>)"); }),
        Catch::Contains("lets light through"));
    CHECK_THAT(errorOf([] { makeBSDF(R"(<bsdf type="twosided"/>)"); }),
               Catch::Contains("twosided: needs 1 nested <bsdf>, got 0"));
}

TEST_CASE("thindielectric reflects R = 2F/(1 + F) and passes the rest straight through",
          "[materials][statistical]") {
    const auto pane = makeBSDF(R"(<bsdf type="thindielectric"/>)");
    for (const float degrees : {0.0f, 50.0f, 80.0f, 130.0f}) {
        const Vector3f wi = incidentDirection(degrees, 1.0f);
        const float fresnel = fresnelDielectric(std::abs(wi.z()), 1.000277f, 1.5046f);
        const double R = 2.0 * fresnel / (1.0 + fresnel);
        PCG32 random(3, 1);
        constexpr int kCount = 200000;
        int reflected = 0;
        for (int i = 0; i < kCount; ++i) {
            BSDFQueryRecord bRec(wi);
            const float u = random.nextFloat();
            const Color3f weight = pane->sample(bRec, Point2f(u, random.nextFloat()));
            CHECK(weight.isApprox(Color3f(1.0f)));
            if (bRec.wo.isApprox(Vector3f(-wi.x(), -wi.y(), wi.z()), 1e-5f))
                ++reflected;
            else
                REQUIRE(bRec.wo.isApprox(Vector3f(-wi), 1e-5f));
        }
        // A binomial count: within 4 standard deviations of kCount·R.
        const double sigma = std::sqrt(kCount * R * (1.0 - R));
        INFO(degrees << "°: " << reflected << " reflected, expected " << kCount * R);
        CHECK(std::abs(reflected - kCount * R) <= 4.0 * sigma + 1.0);
    }
}

TEST_CASE("mix chooses its second BSDF at a fraction `amount` of the points",
          "[materials][statistical]") {
    const auto mix = makeBSDF(R"(<bsdf type="mix"><float name="amount" value="0.3"/>
        <bsdf type="diffuse"><color name="albedo" value="0.2"/></bsdf>
        <bsdf type="diffuse"><color name="albedo" value="0.8"/></bsdf></bsdf>)");
    PCG32 random(12, 1);
    constexpr int kPoints = 100000;
    int second = 0;
    const Vector3f wi = incidentDirection(30.0f), wo = incidentDirection(50.0f, 1.0f);
    for (int i = 0; i < kPoints; ++i) {
        BSDFQueryRecord bRec(wi, wo, ESolidAngle);
        bRec.p = randomPoint(random, 10.0f);
        const float value = mix->eval(bRec).r();
        // The same point answers the same way, whatever the directions.
        BSDFQueryRecord reverse(wo, wi, ESolidAngle);
        reverse.p = bRec.p;
        CHECK(mix->eval(reverse).r() == value);
        if (value > 0.5f * kInvPi)
            ++second;
    }
    const double sigma = std::sqrt(kPoints * 0.3 * 0.7);
    INFO(second << " of " << kPoints);
    CHECK(std::abs(second - 0.3 * kPoints) <= 4.0 * sigma);
}

TEST_CASE("Mitsuba's bumpmap gives its shape the bump map the shape's own `bump` would",
          "[materials][bumpmap]") {
    const std::string heights =
        R"(<texture type="checkerboard" name="{}"><float name="scale" value="6"/>
        <color name="color0" value="0"/><color name="color1" value="0.02"/></texture>)";
    auto render = [&](const std::string &quad) {
        const auto scene = loadScene(R"(<scene><integrator type="path_mis"/>
            <sampler type="independent"><integer name="sampleCount" value="4"/></sampler>
            <camera type="perspective"><transform name="toWorld">
                <lookat origin="0, 1, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
                <float name="fov" value="45"/><integer name="width" value="24"/>
                <integer name="height" value="24"/></camera>
            <emitter type="point"><point name="position" value="1, 2, 1"/>
                <color name="power" value="40"/></emitter>)" +
                                     quad + "</scene>");
        return renderScene(*scene, quietOptions(2)).image;
    };
    const std::string place =
        R"(<transform name="toWorld"><rotate axis="1, 0, 0" angle="-90"/></transform>
        <float name="uvScale" value="2"/>)";
    const Bitmap own = render(R"(<mesh type="rectangle">)" + place + fmt::format(heights, "bump") +
                              R"(<bsdf type="roughconductor"/></mesh>)");
    const Bitmap wrapped =
        render(R"(<mesh type="rectangle">)" + place + R"(<bsdf type="bumpmap">)" +
               fmt::format(heights, "height") + R"(<bsdf type="roughconductor"/></bsdf></mesh>)");
    const Bitmap flat =
        render(R"(<mesh type="rectangle">)" + place + R"(<bsdf type="roughconductor"/></mesh>)");
    CHECK(identicalImages(own, wrapped));
    CHECK_FALSE(identicalImages(own, flat));
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(R"(<mesh type="rectangle"><bsdf type="bumpmap">
                       <bsdf type="diffuse"/></bsdf></mesh>)");
               }),
               Catch::Contains("bumpmap: needs a height texture"));
}
