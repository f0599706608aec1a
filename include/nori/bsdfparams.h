// The parameters of BSDF plugins that may be textures, read once here for every plugin
// that has them: a microfacet roughness `alpha` and a conductor's complex index of
// refraction. The maths they feed lives in microfacet.h and fresnel.h.
#pragma once

#include <nori/bsdf.h>
#include <nori/fresnel.h>
#include <nori/hash.h>
#include <nori/layeredbsdf.h>
#include <nori/microfacet.h>
#include <nori/texture.h>

#include <string>

namespace nori {

/// A microfacet distribution whose roughness may be a texture: the rough BSDFs build the
/// distribution of each query point with at().
class TexturedMicrofacet {
public:
    /// Reads `alpha`, or `alphaU` and `alphaV` (anisotropic: α along the shading frame's
    /// tangent and bitangent, Mitsuba's names), each a positive float or a float texture,
    /// through `textures`; with `remapRoughness` true they are pbrt-v4's roughness r and
    /// α = √r (its RoughnessToAlpha). `plugin` names the BSDF in errors.
    TexturedMicrofacet(MicrofacetDistribution::Type type, const PropertyList &props,
                       TextureParameters &textures, const std::string &plugin);

    /// The distribution at q. Values are clamped to at least kMinAlpha, below which the
    /// lobes underflow in single precision.
    MicrofacetDistribution at(const TextureQuery &q) const {
        const float alphaU = alphaOf(m_alphaU->evalFloat(q));
        if (m_alphaV == m_alphaU)
            return MicrofacetDistribution(m_type, alphaU);
        return MicrofacetDistribution(m_type, alphaU, alphaOf(m_alphaV->evalFloat(q)));
    }
    MicrofacetDistribution::Type type() const { return m_type; }
    /// The parameters as given: "alpha=…", or "alphaU=…, alphaV=…", and the remapping.
    std::string toString() const;

    static constexpr float kMinAlpha = 1e-4f;

private:
    float alphaOf(float value) const {
        return std::max(m_remap ? std::sqrt(std::max(value, 0.0f)) : value, kMinAlpha);
    }
    MicrofacetDistribution::Type m_type;
    std::shared_ptr<const Texture> m_alphaU, m_alphaV; ///< the same texture when isotropic
    bool m_remap = false;
};

/// A conductor's complex index of refraction relative to the outside, η + ik, whose parts
/// may be textures.
struct ConductorIOR {
    std::shared_ptr<const Texture> eta, k;
    float extIOR = 1.0f;
    /// The Fresnel reflectance at the query's point for an incident cosine.
    Color3f fresnel(const TextureQuery &q, float cosThetaI) const;
};

/// Reads a conductor's complex index from a plugin's properties: `material` (a named
/// metal) or `eta` and `k` (colours or textures; default: copper), relative to `extIOR`
/// (default air).
ConductorIOR readConductorIOR(const PropertyList &props, const std::string &plugin,
                              TextureParameters &textures);

/// The coating and base of Mitsuba's plastics (plastic, roughplastic; Mitsuba 0.6
/// documentation): `intIOR`, `extIOR`, `diffuseReflectance`, `specularReflectance`,
/// `nonlinear`, and Mitsuba's weight steering samples to the specular lobe by the mean
/// reflectances.
struct PlasticLayers {
    PlasticLayers(const PropertyList &props, TextureParameters &textures,
                  const std::string &plugin);
    float intIOR, extIOR;
    float invEta2; ///< (extIOR/intIOR)²
    std::shared_ptr<const Texture> diffuse, specular;
    bool nonlinear;
    float specularSamplingWeight; ///< s = mean specular/(mean diffuse + mean specular)

    /// Mitsuba's probability of the specular lobe for its share of the light (F for the
    /// smooth coating, 1 − T for the rough one): share·s/(share·s + (1 − share)(1 − s)).
    float specularProbability(float share) const;
    /// ρ' = ρ/(1 − F_dr), or ρ/(1 − ρ F_dr) when nonlinear: the base with its
    /// interreflections under the coating summed as a geometric series.
    Color3f baseReflectance(const TextureQuery &q, float fdrInternal) const;
    Color3f specularReflectance(const TextureQuery &q) const { return specular->eval(q).max(0.0f); }
    std::string toString() const;
};

/// Reads an index of refraction that may be given as a number or by a material's name
/// (lookupIOR: "water", "bk7", ...), as Mitsuba's `intIOR` and `extIOR` are; `plugin`
/// names the BSDF in errors, which also refuse a non-positive index.
float readIOR(const PropertyList &props, const std::string &name, float defaultValue,
              const std::string &plugin);

/// The roughness of one interface of a layered BSDF (pbrt-v4's `roughness`, `uroughness`,
/// `vroughness` and `remaproughness`), its names under a prefix: "" gives roughness,
/// uRoughness, vRoughness; "interface" gives interfaceRoughness, interfaceURoughness, ...
class LayerRoughness {
public:
    LayerRoughness(const PropertyList &props, TextureParameters &textures,
                   const std::string &plugin, const std::string &prefix);
    /// The interface's microfacets at q: α = √r when remapped (pbrt-v4's RoughnessToAlpha).
    layered::Microfacets at(const TextureQuery &q) const;
    /// Whether the interface is smooth everywhere (constant roughness below the threshold).
    bool alwaysSmooth() const;
    std::string toString() const;

private:
    float alpha(float roughness) const {
        return m_remap ? std::sqrt(std::max(roughness, 0.0f)) : std::max(roughness, 0.0f);
    }
    std::shared_ptr<const Texture> m_u, m_v;
    bool m_remap;
};

/// Reads the random walk of a layered BSDF: thickness, albedo, g, maxDepth, nSamples.
layered::WalkParameters readWalkParameters(const PropertyList &props, const std::string &plugin);
std::string walkToString(const layered::WalkParameters &walk);

/// sample() of a coated BSDF plugin: one walk of `bsdf` for bRec.wi, with weight f·|cos|/pdf
/// of the walk. The first interface's lobe choice takes a number hashed from the sample
/// (the two dimensions choose its microfacet). The coating's mirror reflection, and every
/// sample of a BSDF without a smooth part, is discrete.
template <typename Base>
Color3f sampleCoatedBSDF(const layered::CoatedBSDF<Base> &bsdf, BSDFQueryRecord &bRec,
                         const Point2f &sample, bool smoothPart) {
    const float uc = hashToUnitFloat(hashFloats(sample.x(), sample.y()));
    const layered::Sample s = bsdf.sample(bRec.wi, uc, sample, layered::Transport::Radiance);
    if (!s.valid())
        return Color3f(0.0f);
    bRec.wo = s.wi;
    bRec.eta = 1.0f;
    bRec.measure = s.specular || !smoothPart ? EDiscrete : ESolidAngle;
    return s.f * (std::abs(s.wi.z()) / s.pdf);
}

} // namespace nori
