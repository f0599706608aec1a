#include <nori/fresnel.h>
#include <nori/strutil.h>

#include <complex>
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
    cosThetaI = std::clamp(std::abs(cosThetaI), 0.0f, 1.0f);
    Color3f result;
    for (int c = 0; c < 3; ++c) {
        // With complex η̃ = η + ik: cos θt from Snell's law, then r⊥ and r∥ (PBR 4th ed.
        // §9.3.6), evaluated in complex arithmetic.
        using Complex = std::complex<float>;
        const Complex etaC(eta[c], k[c]);
        const float sin2ThetaI = 1.0f - cosThetaI * cosThetaI;
        const Complex sin2ThetaT = sin2ThetaI / (etaC * etaC);
        const Complex cosThetaT = std::sqrt(Complex(1.0f) - sin2ThetaT);
        const Complex rPerp = (cosThetaI - etaC * cosThetaT) / (cosThetaI + etaC * cosThetaT);
        const Complex rPar = (etaC * cosThetaI - cosThetaT) / (etaC * cosThetaI + cosThetaT);
        result[c] = 0.5f * (std::norm(rPerp) + std::norm(rPar));
    }
    return result;
}

void lookupConductor(const std::string &name, Color3f &eta, Color3f &k) {
    static const std::map<std::string, std::pair<Color3f, Color3f>> kMetals = {
        {"Au", {Color3f(0.143119f, 0.374957f, 1.44248f), Color3f(3.98316f, 2.38572f, 1.60322f)}},
        {"Ag", {Color3f(0.155265f, 0.116723f, 0.138342f), Color3f(4.82835f, 3.12225f, 2.14696f)}},
        {"Cu", {Color3f(0.200438f, 0.924033f, 1.10221f), Color3f(3.91295f, 2.45285f, 2.14219f)}},
        {"Al", {Color3f(1.65746f, 0.880369f, 0.521229f), Color3f(9.22387f, 6.26952f, 4.837f)}},
    };
    auto it = kMetals.find(name);
    if (it == kMetals.end()) {
        std::vector<std::string> names;
        names.reserve(kMetals.size());
        for (const auto &metal : kMetals)
            names.push_back(metal.first);
        throw NoriException("unknown metal '{}'{} (known: {})", name, didYouMean(name, names),
                            fmt::join(names, ", "));
    }
    eta = it->second.first;
    k = it->second.second;
}

} // namespace nori
