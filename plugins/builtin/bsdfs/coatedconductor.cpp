/*
 * coatedconductor — a metal under a dielectric coating, with an optional scattering
 * medium between them, as pbrt-v4 defines it (PBR 4th ed. §14.3.3; Guo, Hašan and Zhao
 * 2018; layeredbsdf.h): car paint, lacquered brass. The conductor's complex index is
 * taken relative to the coating (η/η_coating, k/η_coating), as pbrt-v4 does. eval() and
 * pdf() are unbiased Monte Carlo estimates seeded by the directions; sample() returns one
 * walk with its weight f/pdf. Two-sided. With a smooth coating over a smooth metal and no
 * medium, every lobe is a Dirac one and samples are discrete.
 *
 * Parameters:
 *   interfaceRoughness   float/texture  0     roughness of the coating (GGX)
 *   interfaceURoughness, interfaceVRoughness  float/texture  interfaceRoughness  along the
 *                                              tangent and the bitangent
 *   interfaceEta         float          1.5   index of refraction of the coating
 *   conductorRoughness   float/texture  0     roughness of the metal (GGX)
 *   conductorURoughness, conductorVRoughness  float/texture  conductorRoughness  along the
 *                                              tangent and the bitangent
 *   material             string         —     a named metal (Au, Ag, Cu, Al), instead of
 *                                              conductorEta and conductorK
 *   conductorEta, conductorK  color/texture  copper  the metal's complex index η + ik
 *   reflectance          color/texture  —     instead of η and k: the normal-incidence
 *                                              reflectance r, as η = 1, k = 2√r/√(1 − r)
 *   remapRoughness       boolean        true  roughness r means α = √r, else α = r
 *   thickness            float          0.01  of the medium between coating and metal
 *   albedo               color          0     the medium's single-scattering albedo
 *   g                    float          0     the medium's Henyey–Greenstein asymmetry
 *   maxDepth             integer        10    the most events a walk follows
 *   nSamples             integer        1     walks per estimate of eval() and pdf()
 *
 * Exempt from the sampling test: eval() and pdf() are estimates from random walks, not
 * the density of sample(); tests/test_coated.cpp checks that they are unbiased instead.
 *
 *   <bsdf type="coatedconductor"><float name="conductorRoughness" value="0.2"/>
 *       <string name="material" value="Au"/></bsdf>
 *
 *   <bsdf type="coatedconductor"><float name="interfaceRoughness" value="0.05"/>
 *       <color name="reflectance" value="0.9, 0.6, 0.3"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/layeredbsdf.h>

namespace nori {
namespace {

class CoatedConductor : public BSDF {
public:
    explicit CoatedConductor(const PropertyList &props)
        : m_coating(props, m_textures, "coatedconductor", "interface"),
          m_metal(props, m_textures, "coatedconductor", "conductor"),
          m_walk(readWalkParameters(props, "coatedconductor")) {
        m_eta = props.getFloat("interfaceEta", 1.5f);
        if (!(m_eta > 0.0f))
            throw NoriException("coatedconductor: 'interfaceEta' must be positive, got {}", m_eta);
        const bool named = props.has("material"), reflectance = props.has("reflectance");
        if (int(named) + int(reflectance) +
                int(props.has("conductorEta") || props.has("conductorK")) >
            1)
            throw NoriException("coatedconductor: give one of 'material', 'reflectance' or "
                                "'conductorEta' and 'conductorK'");
        if (reflectance) {
            m_reflectance = m_textures.color(props, "reflectance", Color3f(0.0f));
        } else {
            Color3f eta, k;
            lookupConductor(named ? props.getString("material") : "Cu", eta, k);
            m_conductorEta =
                named ? m_textures.constant(eta) : m_textures.color(props, "conductorEta", eta);
            m_conductorK =
                named ? m_textures.constant(k) : m_textures.color(props, "conductorK", k);
        }
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return sampleCoatedBSDF(at(bRec), bRec, sample, hasSmoothPart(bRec));
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || !hasSmoothPart(bRec))
            return Color3f(0.0f);
        return at(bRec).f(bRec.wi, bRec.wo, layered::Transport::Radiance);
    }
    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || !hasSmoothPart(bRec))
            return 0.0f;
        return at(bRec).pdf(bRec.wi, bRec.wo, layered::Transport::Radiance);
    }
    /// Not a delta distribution unless both interfaces are smooth and nothing scatters
    /// between them.
    bool isDiffuse() const override {
        return !m_coating.alwaysSmooth() || !m_metal.alwaysSmooth() ||
               !(m_walk.albedo == 0.0f).all();
    }

    std::string toString() const override {
        return fmt::format("CoatedConductor[interface {}, interfaceEta={}, conductor {}, {}]",
                           m_coating.toString(), m_eta, m_metal.toString(), walkToString(m_walk));
    }

private:
    layered::CoatedBSDF<layered::Conductor> at(const TextureQuery &q) const {
        Color3f eta, k;
        if (m_reflectance) {
            // pbrt-v4's metal of a given reflectance r at normal incidence: η = 1 and
            // k = 2√r/√(1 − r), whose Fresnel reflectance at 0° is r.
            const Color3f r = m_reflectance->eval(q).max(0.0f).min(0.9999f);
            eta = Color3f(1.0f);
            k = 2.0f * r.sqrt() / (Color3f(1.0f) - r).sqrt();
        } else {
            eta = m_conductorEta->eval(q).max(1e-4f);
            k = m_conductorK->eval(q).max(0.0f);
        }
        // The metal borders the coating, not the air.
        return {layered::Dielectric(m_eta, m_coating.at(q)),
                layered::Conductor(eta / m_eta, k / m_eta, m_metal.at(q)), m_walk};
    }

    bool hasSmoothPart(const TextureQuery &q) const {
        return !m_coating.at(q).smooth() || !m_metal.at(q).smooth() ||
               !(m_walk.albedo == 0.0f).all();
    }

    LayerRoughness m_coating, m_metal;
    float m_eta;
    std::shared_ptr<const Texture> m_reflectance, m_conductorEta, m_conductorK;
    layered::WalkParameters m_walk;
};

NORI_REGISTER_CLASS(CoatedConductor, "coatedconductor");

} // namespace
} // namespace nori
