#include <nori/fresnel.h>
#include <nori/spectrum.h>
#include <nori/strutil.h>

#include "math/spectraldata.h"

#include <algorithm>
#include <map>

namespace nori {

float fresnelDielectric(float cosThetaI, float extIOR, float intIOR) {
    float etaI = extIOR, etaT = intIOR;
    if (extIOR == intIOR)
        return 0.0f;
    // Arriving from inside: swap the indices.
    if (cosThetaI < 0.0f) {
        std::swap(etaI, etaT);
        cosThetaI = -cosThetaI;
    }
    const float eta = etaI / etaT;
    const float sinThetaTSqr = eta * eta * std::max(0.0f, 1.0f - cosThetaI * cosThetaI);
    if (sinThetaTSqr > 1.0f)
        return 1.0f; // total internal reflection
    const float cosThetaT = std::sqrt(1.0f - sinThetaTSqr);
    const float rs = (etaI * cosThetaI - etaT * cosThetaT) / (etaI * cosThetaI + etaT * cosThetaT);
    const float rp = (etaT * cosThetaI - etaI * cosThetaT) / (etaT * cosThetaI + etaI * cosThetaT);
    return 0.5f * (rs * rs + rp * rp);
}

float fresnel(float cosThetaI, float extIOR, float intIOR) {
    return fresnelDielectric(cosThetaI, extIOR, intIOR);
}

Color3f fresnelConductor(float cosThetaI, const Color3f &eta, const Color3f &k) {
    // The complex form r⊥, r∥ with η̃ = η + ik (PBR 4th ed. §9.3.6), rewritten in real
    // arithmetic (PBR 3rd ed. §8.2.1, FrConductor): a² + b² = |η̃² − sin² θi| and
    // a = Re √(η̃² − sin² θi) give Rs, and Rp = Rs·(t3 − t4)/(t3 + t4). The same values
    // without std::complex's division (a library call per channel), for all three
    // channels at once.
    cosThetaI = std::clamp(std::abs(cosThetaI), 0.0f, 1.0f);
    const float cos2ThetaI = cosThetaI * cosThetaI;
    const float sin2ThetaI = 1.0f - cos2ThetaI;
    const Eigen::Array3f eta2 = eta.square(), k2 = k.square();
    const Eigen::Array3f t0 = eta2 - k2 - sin2ThetaI;
    const Eigen::Array3f a2PlusB2 = (t0.square() + 4.0f * eta2 * k2).sqrt();
    const Eigen::Array3f t1 = a2PlusB2 + cos2ThetaI;
    const Eigen::Array3f a = (0.5f * (a2PlusB2 + t0)).max(0.0f).sqrt();
    const Eigen::Array3f t2 = 2.0f * cosThetaI * a;
    const Eigen::Array3f rs = (t1 - t2) / (t1 + t2);
    const Eigen::Array3f t3 = cos2ThetaI * a2PlusB2 + sin2ThetaI * sin2ThetaI;
    const Eigen::Array3f t4 = t2 * sin2ThetaI;
    const Eigen::Array3f rp = rs * (t3 - t4) / (t3 + t4);
    return Color3f(0.5f * (rp + rs));
}

float fresnelDiffuseReflectance(float eta) {
    // Below the critical cosine μc = √(1 − η²) (η < 1) light is totally reflected, F = 1,
    // which contributes 2 ∫₀^μc μ dμ = μc². Above it F has a square-root edge at μc, which
    // the substitution μ = μc + (1 − μc) s² smooths for Simpson's rule.
    const double criticalCosine = eta < 1.0f ? std::sqrt(1.0 - double(eta) * eta) : 0.0;
    constexpr int kIntervals = 4096;
    const double h = 1.0 / kIntervals;
    double sum = 0.0;
    for (int i = 0; i <= kIntervals; ++i) {
        const double s = i * h;
        const double mu = criticalCosine + (1.0 - criticalCosine) * s * s;
        const double jacobian = 2.0 * (1.0 - criticalCosine) * s;
        const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
        sum += weight * mu * jacobian * fresnelDielectric(static_cast<float>(mu), 1.0f, eta);
    }
    return static_cast<float>(criticalCosine * criticalCosine + 2.0 * sum * h / 3.0);
}

float lookupIOR(const std::string &name) {
    // Mitsuba 0.6's table of indices of refraction (its documentation, "dielectric").
    static const std::map<std::string, float> kIndices = {
        {"vacuum", 1.0f},      {"helium", 1.00004f},         {"hydrogen", 1.00013f},
        {"air", 1.00028f},     {"carbon dioxide", 1.00045f}, {"water", 1.3330f},
        {"acetone", 1.36f},    {"ethanol", 1.361f},          {"carbon tetrachloride", 1.461f},
        {"glycerol", 1.4729f}, {"benzene", 1.501f},          {"silicone oil", 1.52045f},
        {"bromine", 1.661f},   {"water ice", 1.31f},         {"fused quartz", 1.458f},
        {"pyrex", 1.470f},     {"acrylic glass", 1.49f},     {"polypropylene", 1.49f},
        {"bk7", 1.5046f},      {"sodium chloride", 1.544f},  {"amber", 1.55f},
        {"pet", 1.5750f},      {"diamond", 2.419f},
    };
    const auto it = kIndices.find(toLower(name));
    if (it == kIndices.end()) {
        std::vector<std::string> names;
        names.reserve(kIndices.size());
        for (const auto &entry : kIndices)
            names.push_back(entry.first);
        throw NoriException("unknown index of refraction '{}'{} (known: {})", name,
                            didYouMean(name, names), fmt::join(names, ", "));
    }
    return it->second;
}

namespace {

/// A measured spectrum from interleaved (λ, value) pairs, held at its end values beyond
/// the measured range out to the CIE tables' 360–830 nm: several of Mitsuba's tables stop
/// short of it (diamond at 656 nm), and an optical constant does not drop to zero there.
PiecewiseLinearSpectrum heldAtItsEnds(const float *pairs, size_t floats) {
    std::vector<float> lambdas, values;
    for (size_t i = 0; i + 1 < floats; i += 2) {
        lambdas.push_back(pairs[i]);
        values.push_back(pairs[i + 1]);
    }
    constexpr float kFirst = 360.0f, kLast = 830.0f;
    if (lambdas.front() > kFirst) {
        lambdas.insert(lambdas.begin(), kFirst);
        values.insert(values.begin(), values.front());
    }
    if (lambdas.back() < kLast) {
        lambdas.push_back(kLast);
        values.push_back(values.back());
    }
    return PiecewiseLinearSpectrum(std::move(lambdas), std::move(values));
}

} // namespace

void lookupConductor(const std::string &name, Color3f &eta, Color3f &k) {
    static const std::map<std::string, std::pair<Color3f, Color3f>> kMetals = {
        {"Au", {Color3f(0.143119f, 0.374957f, 1.44248f), Color3f(3.98316f, 2.38572f, 1.60322f)}},
        {"Ag", {Color3f(0.155265f, 0.116723f, 0.138342f), Color3f(4.82835f, 3.12225f, 2.14696f)}},
        {"Cu", {Color3f(0.200438f, 0.924033f, 1.10221f), Color3f(3.91295f, 2.45285f, 2.14219f)}},
        {"Al", {Color3f(1.65746f, 0.880369f, 0.521229f), Color3f(9.22387f, 6.26952f, 4.837f)}},
        // Mitsuba's "none": η = 0, k = 1 reflects everything at every angle, a perfect mirror.
        {"none", {Color3f(0.0f), Color3f(1.0f)}},
    };
    if (const auto it = kMetals.find(name); it != kMetals.end()) {
        eta = it->second.first;
        k = it->second.second;
        return;
    }
    // Measured spectra, turned into RGB once by the method of spectrum.h: pbrt-v4's
    // brass, MgO and TiO2, then the rest of Mitsuba 0.6's names.
    const auto toRGB = [&](const PiecewiseLinearSpectrum &etaSpectrum,
                           const PiecewiseLinearSpectrum &kSpectrum) {
        eta = reflectanceToRGB([&](float lambda) { return etaSpectrum(lambda); });
        k = reflectanceToRGB([&](float lambda) { return kSpectrum(lambda); }).max(0.0f);
    };
    static const std::vector<std::string> kPbrtSpectral = {"CuZn", "MgO", "TiO2"};
    if (std::find(kPbrtSpectral.begin(), kPbrtSpectral.end(), name) != kPbrtSpectral.end()) {
        toRGB(namedSpectrum("metal-" + name + "-eta"), namedSpectrum("metal-" + name + "-k"));
        return;
    }
    using spectraldata::kMitsubaConductorCount;
    using spectraldata::kMitsubaConductors;
    const auto *end = kMitsubaConductors + kMitsubaConductorCount;
    const auto *measured = std::find_if(
        kMitsubaConductors, end, [&](const auto &conductor) { return name == conductor.name; });
    if (measured != end) {
        toRGB(heldAtItsEnds(measured->eta, measured->etaSize),
              heldAtItsEnds(measured->k, measured->kSize));
        return;
    }
    std::vector<std::string> names;
    names.reserve(kMetals.size() + kPbrtSpectral.size() + kMitsubaConductorCount);
    for (const auto &metal : kMetals)
        names.push_back(metal.first);
    names.insert(names.end(), kPbrtSpectral.begin(), kPbrtSpectral.end());
    for (const auto *conductor = kMitsubaConductors; conductor != end; ++conductor)
        names.emplace_back(conductor->name);
    throw NoriException("unknown metal '{}'{} (known: {})", name, didYouMean(name, names),
                        fmt::join(names, ", "));
}

} // namespace nori
