/*
 * coateddiffuse — a diffuse base under a dielectric coating, with an optional scattering
 * medium between them, as pbrt-v4 defines it (PBR 4th ed. §14.3.3; Guo, Hašan and Zhao
 * 2018; layeredbsdf.h): light is followed on random walks between the coating and the
 * base, so every internal reflection, the coating's roughness and the medium's colour
 * show. eval() and pdf() are unbiased Monte Carlo estimates seeded by the directions
 * (the same directions give the same numbers, so MIS weights stay consistent);
 * sample() returns one walk with its weight f/pdf. Two-sided. A smooth coating's mirror
 * reflection is a discrete sample.
 *
 * Parameters:
 *   reflectance     color/texture  0.5    albedo of the diffuse base
 *   roughness       float/texture  0      roughness of the coating (GGX)
 *   uRoughness, vRoughness  float/texture  roughness  along the tangent and bitangent
 *   remapRoughness  boolean        true   roughness r means α = √r (pbrt-v4's), else α = r
 *   eta             float          1.5    index of refraction of the coating
 *   thickness       float          0.01   of the medium between coating and base
 *   albedo          color          0      the medium's single-scattering albedo (0: none)
 *   g               float          0      the medium's Henyey–Greenstein asymmetry
 *   maxDepth        integer        10     the most events a walk follows
 *   nSamples        integer        1      walks per estimate of eval() and pdf()
 *
 * Exempt from the sampling test: eval() and pdf() are estimates from random walks, not
 * the density of sample(); tests/test_coated.cpp checks that they are unbiased instead.
 *
 *   <bsdf type="coateddiffuse"><color name="reflectance" value="0.6, 0.2, 0.1"/></bsdf>
 *
 *   <bsdf type="coateddiffuse"><float name="roughness" value="0.1"/>
 *       <color name="albedo" value="0.8, 0.5, 0.3"/> <float name="thickness" value="0.2"/>
 *   </bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/layeredbsdf.h>

namespace nori {
namespace {

class CoatedDiffuse : public BSDF {
public:
    explicit CoatedDiffuse(const PropertyList &props)
        : m_coating(props, m_textures, "coateddiffuse", ""),
          m_walk(readWalkParameters(props, "coateddiffuse")) {
        m_reflectance = m_textures.color(props, "reflectance", Color3f(0.5f));
        m_eta = props.getFloat("eta", 1.5f);
        if (!(m_eta > 0.0f))
            throw NoriException("coateddiffuse: 'eta' must be positive, got {}", m_eta);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return sampleCoatedBSDF(at(bRec), bRec, sample, true);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle)
            return Color3f(0.0f);
        return at(bRec).f(bRec.wi, bRec.wo, layered::Transport::Radiance);
    }
    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle)
            return 0.0f;
        return at(bRec).pdf(bRec.wi, bRec.wo, layered::Transport::Radiance);
    }
    /// A diffuse base always scatters smoothly.
    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        return fmt::format("CoatedDiffuse[reflectance={}, {}, eta={}, {}]",
                           m_reflectance->toString(), m_coating.toString(), m_eta,
                           walkToString(m_walk));
    }

private:
    /// The layered model at the query's point.
    layered::CoatedBSDF<layered::Diffuse> at(const TextureQuery &q) const {
        const Color3f reflectance = m_reflectance->eval(q).max(0.0f).min(1.0f);
        return {layered::Dielectric(m_eta, m_coating.at(q)), layered::Diffuse(reflectance), m_walk};
    }

    std::shared_ptr<const Texture> m_reflectance;
    LayerRoughness m_coating;
    float m_eta;
    layered::WalkParameters m_walk;
};

NORI_REGISTER_CLASS(CoatedDiffuse, "coateddiffuse");

} // namespace
} // namespace nori
