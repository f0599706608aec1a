// The Disney principled BSDF: its values against an independent double-precision
// transcription of Burley's disney.brdf, χ² of the whole BSDF and of each lobe, the
// mixture its pdf claims (with a negative control), reciprocity, directional albedo of
// every lobe at the corners of its parameters (the diffuse lobe against its own integral,
// because Burley's retro-reflection gains energy), the mirror limit, and textures.
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/render.h>
#include <nori/samplingroutines.h>
#include <nori/scene.h>
#include <nori/warp.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <array>
#include <iostream>
#include <map>

using namespace nori;
using Catch::Contains;
using nori::testing::chiSquare;
using nori::testing::errorOf;

namespace {

/// Parameter name → value; baseColor is given separately.
using Parameters = std::map<std::string, float>;

std::string disneyXML(const Parameters &parameters, const Color3f &baseColor,
                      const std::string &lobes = "all") {
    std::string xml =
        fmt::format(R"(<bsdf type="disney"><color name="baseColor" value="{}, {}, {}"/>)",
                    baseColor.r(), baseColor.g(), baseColor.b());
    for (const auto &[name, value] : parameters)
        xml += name == "energyConserving"
                   ? fmt::format(R"(<boolean name="{}" value="{}"/>)", name, value != 0.0f)
                   : fmt::format(R"(<float name="{}" value="{}"/>)", name, value);
    return xml + fmt::format(R"(<string name="lobes" value="{}"/></bsdf>)", lobes);
}

std::shared_ptr<BSDF> disney(const Parameters &parameters,
                             const Color3f &baseColor = Color3f(0.8f, 0.5f, 0.3f),
                             const std::string &lobes = "all") {
    auto bsdf =
        std::dynamic_pointer_cast<BSDF>(loadFromXMLString(disneyXML(parameters, baseColor, lobes)));
    REQUIRE(bsdf);
    return bsdf;
}

/// Incident direction at `degrees` from the normal, at an azimuth of 0.5 rad so that
/// anisotropic lobes are seen neither along their tangent nor across it.
Vector3f incident(float degrees) {
    return nori::testing::incidentDirection(degrees, 0.5f);
}

// ---------------------------------------------------------------------------------------
// Burley's BRDF Explorer disney.brdf, transcribed in double precision with its own names,
// sharing nothing with the plugin: the values the plugin must reproduce.

struct Reference {
    std::array<double, 3> baseColor{};
    double metallic = 0, subsurface = 0, specular = 0.5, specularTint = 0, roughness = 0.5,
           anisotropic = 0, sheen = 0, sheenTint = 0, clearcoat = 0, clearcoatGloss = 1;
    /// A planted slip for the negative control: Fd90 = 0.5 + roughness·cos²θd (the
    /// factor 2 lost), which halves the retro-reflection.
    bool slip = false;

    Reference(const Parameters &p, const Color3f &base) {
        baseColor = {base.r(), base.g(), base.b()};
        auto get = [&p](const char *name, double fallback) {
            auto it = p.find(name);
            return it == p.end() ? fallback : static_cast<double>(it->second);
        };
        metallic = get("metallic", 0);
        subsurface = get("subsurface", 0);
        specular = get("specular", 0.5);
        specularTint = get("specularTint", 0);
        roughness = get("roughness", 0.5);
        anisotropic = get("anisotropic", 0);
        sheen = get("sheen", 0);
        sheenTint = get("sheenTint", 0);
        clearcoat = get("clearcoat", 0);
        clearcoatGloss = get("clearcoatGloss", 1);
    }

    static double sqr(double x) { return x * x; }
    static double SchlickFresnel(double u) { return std::pow(std::clamp(1 - u, 0.0, 1.0), 5); }
    static double mix(double a, double b, double t) { return a * (1 - t) + b * t; }
    static double GTR1(double NdotH, double a) {
        if (a >= 1)
            return 1 / kPiDouble;
        const double a2 = a * a, t = 1 + (a2 - 1) * NdotH * NdotH;
        return (a2 - 1) / (kPiDouble * std::log(a2) * t);
    }
    static double GTR2_aniso(double NdotH, double HdotX, double HdotY, double ax, double ay) {
        return 1 / (kPiDouble * ax * ay * sqr(sqr(HdotX / ax) + sqr(HdotY / ay) + NdotH * NdotH));
    }
    static double smithG_GGX(double NdotV, double alphaG) {
        const double a = alphaG * alphaG, b = NdotV * NdotV;
        return 1 / (NdotV + std::sqrt(a + b - a * b));
    }
    static double smithG_GGX_aniso(double NdotV, double VdotX, double VdotY, double ax, double ay) {
        return 1 / (NdotV + std::sqrt(sqr(VdotX * ax) + sqr(VdotY * ay) + sqr(NdotV)));
    }

    /// The BRDF for light L and view V (local frame, N = +z, X = +x, Y = +y), lobe by lobe:
    /// {diffuse, sheen, specular, clearcoat}, each an RGB triple.
    std::array<std::array<double, 3>, 4> lobes(const Eigen::Vector3d &L,
                                               const Eigen::Vector3d &V) const {
        std::array<std::array<double, 3>, 4> out{};
        const double NdotL = L.z(), NdotV = V.z();
        if (NdotL < 0 || NdotV < 0)
            return out;
        const Eigen::Vector3d H = (L + V).normalized();
        const double NdotH = H.z(), LdotH = L.dot(H);
        const double Cdlum = .3 * baseColor[0] + .6 * baseColor[1] + .1 * baseColor[2];
        const double FL = SchlickFresnel(NdotL), FV = SchlickFresnel(NdotV);
        const double Fd90 = 0.5 + (slip ? 1 : 2) * LdotH * LdotH * roughness;
        const double Fd = mix(1, Fd90, FL) * mix(1, Fd90, FV);
        const double Fss90 = LdotH * LdotH * roughness;
        const double Fss = mix(1, Fss90, FL) * mix(1, Fss90, FV);
        const double ss = 1.25 * (Fss * (1 / (NdotL + NdotV) - .5) + .5);
        const double aspect = std::sqrt(1 - anisotropic * .9);
        const double ax = std::max(.001, sqr(roughness) / aspect);
        const double ay = std::max(.001, sqr(roughness) * aspect);
        const double Ds = GTR2_aniso(NdotH, H.x(), H.y(), ax, ay);
        const double FH = SchlickFresnel(LdotH);
        const double Gs = smithG_GGX_aniso(NdotL, L.x(), L.y(), ax, ay) *
                          smithG_GGX_aniso(NdotV, V.x(), V.y(), ax, ay);
        const double Dr = GTR1(NdotH, mix(.1, .001, clearcoatGloss));
        const double Fr = mix(.04, 1, FH);
        const double Gr = smithG_GGX(NdotL, .25) * smithG_GGX(NdotV, .25);
        for (int c = 0; c < 3; ++c) {
            const double Cdlin = baseColor[c];
            const double Ctint = Cdlum > 0 ? Cdlin / Cdlum : 1;
            const double Cspec0 =
                mix(specular * .08 * mix(1, Ctint, specularTint), Cdlin, metallic);
            const double Csheen = mix(1, Ctint, sheenTint);
            out[0][c] = (1 / kPiDouble) * mix(Fd, ss, subsurface) * Cdlin * (1 - metallic);
            out[1][c] = FH * sheen * Csheen * (1 - metallic);
            out[2][c] = Gs * mix(Cspec0, 1, FH) * Ds;
            out[3][c] = .25 * clearcoat * Gr * Fr * Dr;
        }
        return out;
    }
};

/// A direction uniform on the upper hemisphere.
Vector3f randomHemisphereDirection(PCG32 &random) {
    const float u = random.nextFloat();
    return Warp::squareToUniformHemisphere(Point2f(u, random.nextFloat()));
}

/// The largest relative difference between the plugin's f and the reference's (summed
/// over the lobes in `lobeMask`) over random parameter sets and directions.
double largestDifferenceFromReference(bool plantSlip) {
    PCG32 random(11, 12);
    const char *names[] = {"metallic", "subsurface", "specular",  "specularTint",  "anisotropic",
                           "sheen",    "sheenTint",  "clearcoat", "clearcoatGloss"};
    double largest = 0.0;
    for (int set = 0; set < 100; ++set) {
        Parameters p;
        for (const char *name : names)
            p[name] = random.nextFloat();
        // Roughness from 0.3 up: the narrowest specular lobe tested has α ≈ 0.03, whose
        // value single precision still evaluates to ~1e-5 relative error.
        p["roughness"] = 0.3f + 0.7f * random.nextFloat();
        const Color3f base(random.nextFloat(), random.nextFloat(), random.nextFloat());
        Reference reference(p, base);
        reference.slip = plantSlip;
        auto bsdf = disney(p, base);
        for (int pair = 0; pair < 50; ++pair) {
            const Vector3f wi = randomHemisphereDirection(random),
                           wo = randomHemisphereDirection(random);
            const auto lobes = reference.lobes(wo.cast<double>(), wi.cast<double>());
            const Color3f f = bsdf->eval(BSDFQueryRecord(wi, wo, ESolidAngle));
            for (int c = 0; c < 3; ++c) {
                const double expected = lobes[0][c] + lobes[1][c] + lobes[2][c] + lobes[3][c];
                largest = std::max(largest, std::abs(f[c] - expected) / (expected + 1e-4));
            }
        }
    }
    return largest;
}

// ---------------------------------------------------------------------------------------

const std::vector<float> kAngles = {0.0f, 30.0f, 60.0f, 85.0f};

/// Corners and middles of the parameter space for the χ² tests on the sphere's histogram.
/// Roughness stops at 0.25 (α = 0.06) and clearcoatGloss at 0.6 (α = 0.04) here: sharper
/// lobes fall inside one histogram cell. tests/test_sharplobes.cpp tests roughness down
/// to 0.05 in half-vector coordinates, and the mirror-limit test covers roughness 0.
const std::vector<Parameters> kParameterSets = {
    {},
    {{"metallic", 0},
     {"roughness", 1},
     {"specular", 1},
     {"specularTint", 1},
     {"subsurface", 1},
     {"sheen", 1},
     {"sheenTint", 1},
     {"clearcoat", 1},
     {"clearcoatGloss", 0},
     {"anisotropic", 1}},
    {{"metallic", 1}, {"roughness", 1}, {"anisotropic", 1}},
    {{"metallic", 1}, {"roughness", 0.25f}},
    {{"metallic", 0},
     {"roughness", 0.25f},
     {"specular", 1},
     {"clearcoat", 1},
     {"clearcoatGloss", 0.6f}},
    {{"metallic", 0}, {"specular", 0}, {"roughness", 0.25f}, {"clearcoatGloss", 0}},
    {{"metallic", 0.5f},
     {"subsurface", 0.5f},
     {"specular", 0.5f},
     {"specularTint", 0.5f},
     {"roughness", 0.5f},
     {"anisotropic", 0.5f},
     {"sheen", 0.5f},
     {"sheenTint", 0.5f},
     {"clearcoat", 0.5f},
     {"clearcoatGloss", 0.5f}},
    {{"metallic", 1}, {"roughness", 0.5f}, {"clearcoat", 1}, {"clearcoatGloss", 0}},
    {{"metallic", 0.3f},
     {"roughness", 0.6f},
     {"anisotropic", 1},
     {"clearcoat", 0.5f},
     {"clearcoatGloss", 0.3f}},
    {{"metallic", 1},
     {"subsurface", 1},
     {"specular", 1},
     {"specularTint", 1},
     {"roughness", 1},
     {"anisotropic", 1},
     {"sheen", 1},
     {"sheenTint", 1},
     {"clearcoat", 1},
     {"clearcoatGloss", 0.6f}},
};

/// Each lobe alone (the `lobes` parameter), with parameters that exercise it.
struct LobeCase {
    std::string lobe;
    Parameters parameters;
};
const std::vector<LobeCase> kLobeCases = {
    {"diffuse", {{"roughness", 0.8f}}},
    {"diffuse", {{"roughness", 0.3f}, {"subsurface", 1}}},
    {"sheen", {{"sheen", 1}, {"sheenTint", 0.5f}}},
    {"specular", {{"roughness", 0.4f}}},
    {"specular", {{"roughness", 0.6f}, {"anisotropic", 1}, {"metallic", 1}}},
    {"clearcoat", {{"clearcoat", 1}, {"clearcoatGloss", 0}}},
    {"clearcoat", {{"clearcoat", 0.5f}, {"clearcoatGloss", 0.5f}}},
};

/// Mean and standard error, per channel, of the weights sample() returns for wi: the
/// directional albedo ∫ f |cos θo| dωo.
std::pair<Color3f, Color3f> albedo(const BSDF &bsdf, const Vector3f &wi, int n) {
    PCG32 random(21, 22);
    Eigen::Array3d sum = Eigen::Array3d::Zero(), sum2 = Eigen::Array3d::Zero();
    for (int i = 0; i < n; ++i) {
        BSDFQueryRecord bRec(wi);
        const float u = random.nextFloat();
        const Eigen::Array3d w = bsdf.sample(bRec, Point2f(u, random.nextFloat())).cast<double>();
        sum += w;
        sum2 += w * w;
    }
    const Eigen::Array3d mean = sum / n;
    const Eigen::Array3d error = ((sum2 / n - mean * mean).max(0.0) / n).sqrt();
    return {mean.cast<float>(), error.cast<float>()};
}

/// ∫ f(wi, wo) cos θo dωo of a function of wo by adaptive Simpson in (cos θo, φo).
double hemisphereIntegral(const std::function<double(const Eigen::Vector3d &)> &f) {
    return adaptiveSimpson2D(
        [&f](double cosTheta, double phi) {
            const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
            return f(Eigen::Vector3d(sinTheta * std::cos(phi), sinTheta * std::sin(phi),
                                     cosTheta)) *
                   cosTheta;
        },
        0.0, 0.0, 1.0, 2.0 * kPiDouble, 1e-7, 12);
}

/// Every combination of the listed parameters at 0 and 1, on top of `base`.
std::vector<Parameters> corners(const std::vector<std::string> &names,
                                const Parameters &base = {}) {
    std::vector<Parameters> out;
    for (unsigned bits = 0; bits < (1u << names.size()); ++bits) {
        Parameters p = base;
        for (size_t i = 0; i < names.size(); ++i)
            p[names[i]] = (bits >> i) & 1u ? 1.0f : 0.0f;
        out.push_back(p);
    }
    return out;
}

} // namespace

TEST_CASE("Disney BSDF values match Burley's disney.brdf", "[disney]") {
    // Float against double on lobes down to α ≈ 0.03: 1e-3 relative is ~100 ulps.
    CHECK(largestDifferenceFromReference(false) < 1e-3);
    // Negative control: the reference with Fd90's factor 2 lost is told apart.
    CHECK(largestDifferenceFromReference(true) > 1e-2);
}

TEST_CASE("Disney BSDF samples its pdf at corners and middles of its parameters",
          "[disney][chi2]") {
    const double level =
        sidakCorrection(0.01, static_cast<int>(kParameterSets.size() * kAngles.size()));
    uint64_t seed = 300;
    for (const Parameters &parameters : kParameterSets) {
        auto bsdf = disney(parameters);
        for (float angle : kAngles) {
            const ChiSquareReport report =
                chiSquare(bsdfRoutine(*bsdf, incident(angle)), ++seed, level);
            INFO(bsdf->toString() << " at " << angle << " degrees: " << report.result.message);
            CHECK(report.result.passed);
        }
    }
}

TEST_CASE("Each Disney lobe alone samples its pdf", "[disney][chi2]") {
    const double level =
        sidakCorrection(0.01, static_cast<int>(kLobeCases.size() * kAngles.size()));
    uint64_t seed = 400;
    for (const LobeCase &lobe : kLobeCases) {
        auto bsdf = disney(lobe.parameters, Color3f(0.8f, 0.5f, 0.3f), lobe.lobe);
        for (float angle : kAngles) {
            const ChiSquareReport report =
                chiSquare(bsdfRoutine(*bsdf, incident(angle)), ++seed, level);
            INFO(bsdf->toString() << " at " << angle << " degrees: " << report.result.message);
            CHECK(report.result.passed);
        }
    }
}

TEST_CASE("Disney's pdf is the mixture of its lobes by Burley's weights", "[disney][chi2]") {
    // Weights: diffuse 1 − metallic, specular 1, clearcoat clearcoat/4, normalised.
    const Parameters p = {{"metallic", 0.2f},
                          {"roughness", 0.5f},
                          {"clearcoat", 1},
                          {"clearcoatGloss", 0.2f},
                          {"sheen", 1}};
    auto whole = disney(p);
    auto diffuse = disney(p, Color3f(0.8f, 0.5f, 0.3f), "diffuse");
    auto specular = disney(p, Color3f(0.8f, 0.5f, 0.3f), "specular");
    auto clearcoat = disney(p, Color3f(0.8f, 0.5f, 0.3f), "clearcoat");
    const std::array<double, 3> weights = {0.8 / 2.05, 1.0 / 2.05, 0.25 / 2.05};
    auto mixture = [&](const std::array<double, 3> &w, const BSDFQueryRecord &bRec) {
        return w[0] * diffuse->pdf(bRec) + w[1] * specular->pdf(bRec) + w[2] * clearcoat->pdf(bRec);
    };
    PCG32 random(31, 32);
    for (int i = 0; i < 1000; ++i) {
        const BSDFQueryRecord bRec(randomHemisphereDirection(random),
                                   randomHemisphereDirection(random), ESolidAngle);
        INFO("wi " << bRec.wi.transpose() << ", wo " << bRec.wo.transpose());
        CHECK(whole->pdf(bRec) == Approx(mixture(weights, bRec)).epsilon(1e-5));
    }
    // Negative control: sample() as it is, against a pdf whose mixture weights are off
    // (the lobes chosen with equal probability), is rejected.
    for (float angle : kAngles) {
        SamplingRoutine routine = bsdfRoutine(*whole, incident(angle));
        const Vector3f wi = incident(angle);
        routine.pdf = [&, wi](const Vector3f &wo) {
            return mixture({1.0 / 3, 1.0 / 3, 1.0 / 3}, BSDFQueryRecord(wi, wo, ESolidAngle));
        };
        INFO("at " << angle << " degrees");
        CHECK_FALSE(chiSquare(routine, 77, 0.01).result.passed);
    }
}

TEST_CASE("Every Disney lobe is reciprocal", "[disney]") {
    // The largest relative difference between f(wi, wo) and f(wo, wi) over random pairs.
    auto asymmetry = [](const std::function<Color3f(const Vector3f &, const Vector3f &)> &f) {
        PCG32 random(41, 42);
        double largest = 0.0;
        for (int i = 0; i < 20000; ++i) {
            const Vector3f a = randomHemisphereDirection(random),
                           b = randomHemisphereDirection(random);
            const Color3f ab = f(a, b), ba = f(b, a);
            largest = std::max(largest, static_cast<double>((ab - ba).abs().maxCoeff() /
                                                            (ab.abs().maxCoeff() + 1e-4f)));
        }
        return largest;
    };
    for (const std::string lobe : {"diffuse", "sheen", "specular", "clearcoat"})
        for (const Parameters &p : {kParameterSets[1], kParameterSets[6],
                                    Parameters{{"metallic", 0.2f},
                                               {"roughness", 0.35f},
                                               {"sheen", 1},
                                               {"clearcoat", 1},
                                               {"clearcoatGloss", 0.4f},
                                               {"anisotropic", 0.7f},
                                               {"subsurface", 0.3f}}}) {
            auto bsdf = disney(p, Color3f(0.8f, 0.5f, 0.3f), lobe);
            auto f = [&](const Vector3f &wi, const Vector3f &wo) {
                return bsdf->eval(BSDFQueryRecord(wi, wo, ESolidAngle));
            };
            INFO(bsdf->toString());
            CHECK(asymmetry(f) < 1e-4);
            // Negative control: the same lobe weighted by cos θi is not reciprocal.
            CHECK(asymmetry([&](const Vector3f &wi, const Vector3f &wo) {
                      return Color3f(f(wi, wo) * (0.5f + 0.5f * wi.z()));
                  }) > 1e-2);
        }
}

TEST_CASE("Disney's specular, sheen and clearcoat lobes never reflect more than arrives",
          "[disney][energy]") {
    // Every corner of the parameters each lobe depends on, with white and saturated base
    // colours (the tints divide by luminance, up to 10× in blue), per channel.
    const std::vector<Color3f> bases = {Color3f(1.0f), Color3f(0.0f, 0.0f, 1.0f),
                                        Color3f(1.0f, 0.0f, 0.0f), Color3f(0.0f)};
    const std::vector<std::pair<std::string, std::vector<Parameters>>> lobes = {
        {"specular", corners({"metallic", "specular", "specularTint", "roughness", "anisotropic"})},
        {"sheen", corners({"metallic", "sheenTint", "roughness"}, {{"sheen", 1}})},
        {"clearcoat", corners({"clearcoatGloss", "roughness"}, {{"clearcoat", 1}})}};
    double largest = 0.0;
    for (const auto &[lobe, sets] : lobes)
        for (const Parameters &p : sets)
            for (const Color3f &base : bases) {
                auto bsdf = disney(p, base, lobe);
                for (float angle : {0.0f, 45.0f, 80.0f, 89.0f}) {
                    const auto [mean, error] = albedo(*bsdf, incident(angle), 20000);
                    INFO(bsdf->toString() << " at " << angle << ": albedo " << mean.transpose()
                                          << " ± " << error.transpose());
                    // At most 1 beyond 4 standard errors of the estimate.
                    CHECK((mean <= 1.0f + 4.0f * error + 1e-6f).all());
                    largest = std::max(largest, static_cast<double>(mean.maxCoeff()));
                }
            }
    std::cout << "Disney specular/sheen/clearcoat lobes: largest directional albedo " << largest
              << "\n";
}

TEST_CASE("Disney's albedo is the sum of its lobes' albedos", "[disney][energy]") {
    // The lobes are added, not layered (Burley 2012): the whole BSDF's albedo, sampled
    // through its mixture, equals the sum of the lobes' albedos sampled alone. Where that
    // sum exceeds 1 is Burley's model, not a sampling error; the figure is printed.
    const std::vector<std::string> lobes = {"diffuse", "sheen", "specular", "clearcoat"};
    double largest = 0.0, largestSmooth = 0.0;
    std::string where;
    for (const Parameters &p : corners({"metallic", "specular", "roughness", "sheen", "clearcoat"}))
        for (float angle : {0.0f, 60.0f, 89.0f}) {
            const Vector3f wi = incident(angle);
            auto whole = disney(p, Color3f(1.0f));
            const auto [mean, error] = albedo(*whole, wi, 40000);
            Color3f sum(0.0f), sumError2(0.0f);
            for (const std::string &lobe : lobes) {
                const auto [lobeMean, lobeError] =
                    albedo(*disney(p, Color3f(1.0f), lobe), wi, 40000);
                sum += lobeMean;
                sumError2 += lobeError * lobeError;
            }
            const Color3f tolerance = 4.0f * (error * error + sumError2).sqrt() + 1e-5f;
            INFO(whole->toString() << " at " << angle << ": albedo " << mean.r() << " ± "
                                   << error.r() << ", lobes' sum " << sum.r());
            CHECK(((mean - sum).abs() <= tolerance).all());
            if (mean.r() > largest) {
                largest = mean.r();
                where = fmt::format("{} at {} degrees", whole->toString(), angle);
            }
            // At roughness 0 the diffuse lobe has no retro-reflection gain.
            if (p.at("roughness") == 0.0f)
                largestSmooth = std::max(largestSmooth, static_cast<double>(mean.r()));
        }
    std::cout << "Disney (white baseColor): largest directional albedo " << largest << ", " << where
              << "; at roughness 0: " << largestSmooth << "\n";
}

TEST_CASE("Energy-conserving Disney reflects at most what arrives, at every corner",
          "[disney][energy]") {
    // Every corner of the ten parameters, under a white and a blue base colour (the tints
    // divide by luminance: ×10 in blue), at three angles: the layered model's directional
    // albedo stays within 1 (beyond 4 standard errors of the estimate), per channel.
    // Negative control: Burley's additive model, the same corners, exceeds it (1.70).
    const std::vector<std::string> names = {
        "metallic",    "subsurface", "specular",  "specularTint", "roughness",
        "anisotropic", "sheen",      "sheenTint", "clearcoat",    "clearcoatGloss"};
    // The BSDFs are loaded here (Catch's REQUIRE is for one thread), their albedos
    // estimated in parallel (each from its own fixed seed), and judged in order below.
    struct Case {
        Parameters parameters;
        Color3f base;
        std::shared_ptr<BSDF> additive, layered;
        float angle;
        int samples;
        std::pair<Color3f, Color3f> albedo, additiveAlbedo;
    };
    std::vector<Case> cases;
    for (Parameters p : corners(names))
        for (const Color3f &base : {Color3f(1.0f), Color3f(0.0f, 0.0f, 1.0f)}) {
            const auto additive = disney(p, base);
            p["energyConserving"] = 1.0f;
            const auto layered = disney(p, base);
            p.erase("energyConserving");
            // More samples at grazing angles, where the albedos are largest and noisiest.
            for (const auto &[angle, samples] :
                 {std::pair{0.0f, 3000}, std::pair{85.0f, 8000}, std::pair{89.0f, 20000}})
                cases.push_back({p, base, additive, layered, angle, samples, {}, {}});
        }
    parallelFor(size_t(0), cases.size(), [&cases](size_t i) {
        Case &c = cases[i];
        c.albedo = albedo(*c.layered, incident(c.angle), c.samples);
        c.additiveAlbedo = albedo(*c.additive, incident(c.angle), 2000);
    });
    double largest = 0.0, smallestWhite = 1.0, largestAdditive = 0.0;
    std::string where, whereSmallest;
    int exceeded = 0, additiveExceeded = 0;
    for (const Case &c : cases) {
        const auto &[mean, error] = c.albedo;
        if (!(mean <= 1.0f + 4.0f * error + 1e-6f).all()) {
            ++exceeded;
            UNSCOPED_INFO(c.layered->toString() << " at " << c.angle << ": albedo "
                                                << mean.transpose() << " ± " << error.transpose());
        }
        if (mean.maxCoeff() > largest) {
            largest = mean.maxCoeff();
            where = fmt::format("{} at {} degrees", c.layered->toString(), c.angle);
        }
        // The light layering loses: white, metallic 0, at normal incidence.
        if (c.base.b() == 1.0f && c.base.r() == 1.0f && c.angle == 0.0f &&
            c.parameters.at("metallic") == 0.0f && mean.r() < smallestWhite) {
            smallestWhite = mean.r();
            whereSmallest = c.layered->toString();
        }
        const auto &[additiveMean, additiveError] = c.additiveAlbedo;
        if (!(additiveMean <= 1.0f + 4.0f * additiveError + 1e-6f).all())
            ++additiveExceeded;
        largestAdditive = std::max(largestAdditive, static_cast<double>(additiveMean.maxCoeff()));
    }
    CHECK(exceeded == 0);
    CHECK(additiveExceeded > 0);
    std::cout << "Energy-conserving Disney: largest directional albedo " << largest << " (" << where
              << "); smallest at normal incidence, white, metallic 0: " << smallestWhite << " ("
              << whereSmallest << ")"
              << "; additive model at the same corners: largest " << largestAdditive << ", "
              << additiveExceeded << " cases above 1\n";
}

TEST_CASE("Disney's diffuse lobe has its integral's albedo, retro-reflection gain included",
          "[disney][energy]") {
    // Burley's diffuse is not energy-conserving: Fd90 = 1/2 + 2 roughness cos²θd exceeds
    // 1 at grazing angles. sample()'s mean weight must equal the reference's integral.
    double gain = 0.0;
    for (const Parameters &p : corners({"roughness", "subsurface"}))
        for (float angle : {0.0f, 30.0f, 60.0f, 85.0f, 89.0f}) {
            auto bsdf = disney(p, Color3f(1.0f), "diffuse");
            const Vector3f wi = incident(angle);
            const Reference reference(p, Color3f(1.0f));
            const double integral = hemisphereIntegral([&](const Eigen::Vector3d &wo) {
                return reference.lobes(wo, wi.cast<double>())[0][0];
            });
            const auto [mean, error] = albedo(*bsdf, wi, 200000);
            INFO(bsdf->toString() << " at " << angle << ": sampled " << mean.r() << " ± "
                                  << error.r() << ", integral " << integral);
            CHECK(std::abs(mean.r() - integral) <= 4.0 * error.r() + 1e-4);
            gain = std::max(gain, integral);
        }
    std::cout << "Disney diffuse lobe (white): largest directional albedo " << gain << "\n";
    // Burley's retro-reflection is there: at roughness 1 and 89° the white diffuse lobe
    // reflects about half again what arrives (1.52 by the integral).
    CHECK(gain > 1.4);
    CHECK(gain < 1.6);
}

TEST_CASE("Disney at metallic 1 and roughness 0 is a mirror with Schlick's Fresnel", "[disney]") {
    const Color3f base(0.9f, 0.5f, 0.2f);
    for (float angle : {0.0f, 30.0f, 60.0f, 80.0f}) {
        const Vector3f wi = incident(angle);
        auto mirror = disney({{"metallic", 1}, {"roughness", 0}}, base);
        const auto [mean, error] = albedo(*mirror, wi, 20000);
        const float weight = std::pow(1.0f - wi.z(), 5.0f);
        const Color3f schlick = base + (Color3f(1.0f) - base) * weight;
        INFO("at " << angle << ": albedo " << mean.transpose() << ", Schlick "
                   << schlick.transpose());
        // α = 0.001: G1 ≥ 1 − 1e-5 and the half vectors stray by ~1e-3 rad from the normal.
        CHECK((mean - schlick).abs().maxCoeff() < 2e-3f);
        // The samples leave in the mirror direction: GGX's tail puts a fraction
        // α²/(α² + tan²θ) of the normals beyond θ, about 1% beyond 0.01 rad (2θ = 0.02 in wo).
        PCG32 random(51, 52);
        const Vector3f mirrored(-wi.x(), -wi.y(), wi.z());
        int near = 0;
        for (int i = 0; i < 1000; ++i) {
            BSDFQueryRecord bRec(wi);
            const float u = random.nextFloat();
            mirror->sample(bRec, Point2f(u, random.nextFloat()));
            near += (bRec.wo - mirrored).norm() < 0.02f;
        }
        CHECK(near >= 970);
        // ... and rougher surfaces approach that limit from further away.
        auto distanceToSchlick = [&](float roughness) {
            auto bsdf = disney({{"metallic", 1}, {"roughness", roughness}}, base);
            return (albedo(*bsdf, wi, 20000).first - schlick).abs().maxCoeff();
        };
        const float smoother = distanceToSchlick(0.3f), rougher = distanceToSchlick(0.6f);
        CHECK(rougher > smoother);
        CHECK(smoother > (mean - schlick).abs().maxCoeff());
    }
}

TEST_CASE("Disney with textured parameters samples its pdf at every texel", "[disney][chi2]") {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(R"(
        <bsdf type="disney">
            <texture type="checkerboard" name="baseColor">
                <color name="color0" value="0.1, 0.3, 0.6"/> <color name="color1" value="0.9"/>
            </texture>
            <texture type="checkerboard" name="metallic">
                <color name="color0" value="0"/> <color name="color1" value="1"/>
            </texture>
            <float name="clearcoat" value="1"/> <float name="clearcoatGloss" value="0.3"/>
        </bsdf>)"));
    REQUIRE(bsdf);
    // The checkerboard (scale 2) has color0 at uv (0.25, 0.25) and color1 at (0.75, 0.25).
    const std::vector<std::pair<Point2f, Parameters>> cells = {
        {Point2f(0.25f, 0.25f), {{"metallic", 0}, {"clearcoat", 1}, {"clearcoatGloss", 0.3f}}},
        {Point2f(0.75f, 0.25f), {{"metallic", 1}, {"clearcoat", 1}, {"clearcoatGloss", 0.3f}}}};
    const std::vector<Color3f> colors = {Color3f(0.1f, 0.3f, 0.6f), Color3f(0.9f)};
    const double level = sidakCorrection(0.01, 2 * static_cast<int>(kAngles.size()));
    uint64_t seed = 500;
    for (size_t cell = 0; cell < cells.size(); ++cell) {
        const TextureQuery where(cells[cell].first);
        // The lobes see the texel's values: the same as a constant BSDF of them.
        auto constant = disney(cells[cell].second, colors[cell]);
        for (float angle : kAngles) {
            BSDFQueryRecord bRec(incident(angle), incident(angle + 5.0f), ESolidAngle);
            static_cast<TextureQuery &>(bRec) = where;
            const BSDFQueryRecord plain(bRec.wi, bRec.wo, ESolidAngle);
            INFO("uv " << where.uv.transpose() << " at " << angle);
            CHECK((bsdf->eval(bRec) - constant->eval(plain)).abs().maxCoeff() < 1e-5f);
            const ChiSquareReport report =
                chiSquare(bsdfRoutine(*bsdf, incident(angle), where), ++seed, level);
            INFO(report.result.message);
            CHECK(report.result.passed);
        }
    }
}

TEST_CASE("Disney's bad parameters get clear errors", "[disney]") {
    auto error = [](const std::string &xml) { return errorOf([&] { loadFromXMLString(xml); }); };
    CHECK_THAT(error(R"(<bsdf type="disney"><float name="metallic" value="1.5"/></bsdf>)"),
               Contains("'metallic' must be in [0, 1], got 1.5"));
    CHECK_THAT(error(R"(<bsdf type="disney"><color name="baseColor" value="0.5"/>)"
                     R"(<color name="albedo" value="0.5"/></bsdf>)"),
               Contains("'baseColor' or its alias 'albedo', not both"));
    CHECK_THAT(
        error(R"(<bsdf type="disney"><color name="baseColor" value="1.2, 0.5, 0.5"/></bsdf>)"),
        Contains("'baseColor' must lie in [0, 1]"));
    CHECK_THAT(
        error(R"(<bsdf type="disney"><string name="lobes" value="diffuse, specualr"/></bsdf>)"),
        Contains("unknown lobe 'specualr' in 'lobes' (did you mean 'specular'?)"));
    CHECK_THAT(error(R"(<bsdf type="disney"><float name="roughnes" value="0.2"/></bsdf>)"),
               Contains("roughnes"));
    // The alias reads like baseColor.
    auto alias = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(
        R"(<bsdf type="disney"><color name="albedo" value="0.2, 0.4, 0.6"/></bsdf>)"));
    auto named = disney({}, Color3f(0.2f, 0.4f, 0.6f));
    const BSDFQueryRecord bRec(incident(20), incident(50), ESolidAngle);
    CHECK((alias->eval(bRec) - named->eval(bRec)).abs().maxCoeff() == 0.0f);
}

TEST_CASE("The Disney parameter sweep example renders", "[disney][render]") {
    // The example scene at a fifth of its size: every one of its 60 materials loads and
    // every sample is finite and non-negative.
    auto scene = std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/disney/sweep.xml",
                    LoadOptions(Defines{{"width", "72"}, {"height", "120"}, {"spp", "16"}})));
    REQUIRE(scene);
    const RenderResult result = renderScene(*scene, nori::testing::quietOptions(2));
    CHECK(result.invalidSamples == 0);
    CHECK(result.image.mean().getLuminance() > 0.0f);
}
