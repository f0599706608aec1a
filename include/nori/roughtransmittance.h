// The transmittance of a rough dielectric boundary: the fraction of light from a direction
// at cos θ = μ that a microfacet interface of roughness α lets through,
// T(μ, α) = ∫ f_t(wi, wo) |cos θo| dωo, with f_t Walter et al. 2007's BTDF (eq. 21) and
// Smith's shadowing. Layered models of a coating over a diffuse base (Mitsuba's
// `roughplastic`; Weidlich and Wilkie 2007) scale the base by it on the way in and out.
#pragma once

#include <nori/albedotable.h>
#include <nori/microfacet.h>

namespace nori {

class RoughTransmittance {
public:
    /// The largest roughness tabulated; lookups clamp α to [0, kMaxAlpha].
    static constexpr float kMaxAlpha = 1.0f;

    /// The table of a distribution type and a relative index η = η_t/η_i (η < 1: from the
    /// denser side, where total internal reflection takes its share). Built once per pair
    /// (64 cosines × 32 roughnesses, 1024 Sobol' samples each, in parallel) and shared.
    static const RoughTransmittance &get(MicrofacetDistribution::Type type, float eta);

    /// T(μ, α), interpolated between the nodes (μ and α clamped to the table).
    float operator()(float mu, float alpha) const {
        return m_table(mu, std::min(alpha, kMaxAlpha) / kMaxAlpha);
    }
    /// The transmittance of light arriving from a diffuse (cosine-weighted) distribution,
    /// 2 ∫₀¹ T(μ, α) μ dμ: one minus the rough counterpart of the Fresnel diffuse
    /// reflectance.
    float diffuse(float alpha) const;

    RoughTransmittance(MicrofacetDistribution::Type type, float eta);

private:
    AlbedoTable m_table;
    std::vector<float> m_diffuse; ///< diffuse() at each roughness node of the table
};

} // namespace nori
