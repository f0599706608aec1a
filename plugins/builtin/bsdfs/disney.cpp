/*
 * disney — Burley's principled BSDF (Burley 2012, "Physically-Based Shading at Disney",
 * and the BRDF Explorer's disney.brdf): a sum of lobes,
 *   f = (1 − metallic) (baseColor/π · mix(Fd, Fss, subsurface) + sheen·FH·Csheen)
 *       + D_GTR2·F·G/(4 cos θi cos θo) + clearcoat/4 · D_GTR1·Fc·Gc/(4 cos θi cos θo).
 * The diffuse term Fd has Burley's retro-reflection (Fd90 = 1/2 + 2 roughness cos²θd),
 * which gains energy: a white diffuse lobe at roughness 1 reflects 1.52 times the light
 * arriving at 89° (tests/test_disney.cpp); Fss is the Hanrahan–Krueger-like flattening.
 * The specular lobe is anisotropic GGX (αx = roughness²/aspect, αy = roughness²·aspect,
 * aspect = √(1 − 0.9 anisotropic), both at least 0.001) with Schlick's Fresnel from
 * Cspec0 = mix(0.08 specular·mix(1, tint, specularTint), baseColor, metallic), sampled
 * by its visible normals; the clearcoat is GTR1 (α = mix(0.1, 0.001, clearcoatGloss))
 * with the Fresnel of IOR 1.5 (F0 = 0.04) and GGX shadowing of α = 0.25. Sampling picks
 * a lobe with probability in proportion to diffuse 1 − metallic (cosine-weighted, also
 * for sheen), specular 1, clearcoat clearcoat/4, and pdf() is that weighted mixture.
 * As in Burley's model the lobes are added, not layered, so a white, fully coated
 * material reflects more than arrives at grazing angles: its directional albedo reaches
 * 1.70 (at 89°; 1.56 at roughness 0); each lobe alone but the diffuse one stays within 1.
 * energyConserving layers the lobes instead, by albedo scaling (Kulla & Conty 2017,
 * "Revisiting Physically Based Shading at Imageworks"): clearcoat over specular over
 * the base of sheen over diffuse, each layer beneath scaled by (1 − E(θi))(1 − E(θo)),
 * E the directional albedo of the layer above (tabulated once over angle and roughness
 * or gloss; the specular's Schlick Fresnel splits it into two tables), a form that stays
 * reciprocal. The diffuse lobe is divided by its largest albedo over angles when that
 * exceeds 1 (1.52 at roughness 1; the retro-reflection's shape stays), the sheen likewise.
 * Then no parameter set reflects more than arrives (tests/test_disney.cpp); the price is
 * the light the layers' inter-reflections would return and, for the diffuse lobe, its
 * gain divided away at every angle: a white, non-metallic corner reflects 0.47 to 1 at
 * normal incidence (0.47 with subsurface, roughness, sheen and coat all at 1).
 * baseColor is linear RGB like every colour in Nori (the Explorer's mon2lin is not applied).
 * The anisotropy follows the shading frame's tangent: dp/du, or a mesh's uv tangents.
 *
 * Parameters:
 *   baseColor       color/texture  0.82, 0.67, 0.16  surface colour, in [0, 1]
 *                                  (Burley's default)
 *   albedo          color/texture  —      another name for baseColor (give one of the two)
 *   metallic        float/texture  0      0: dielectric, 1: metal; in [0, 1] like all below
 *   subsurface      float/texture  0      blends the diffuse lobe toward Fss
 *   specular        float/texture  0.5    normal-incidence reflectance 0.08·specular
 *   specularTint    float/texture  0      tints that reflectance toward baseColor's hue
 *   roughness       float/texture  0.5    roughness of the diffuse and specular lobes
 *   anisotropic     float/texture  0      0: isotropic, 1: 10:1 aspect along the tangent
 *   sheen           float/texture  0      grazing-angle sheen for cloth
 *   sheenTint       float/texture  0      tints the sheen toward baseColor's hue
 *   clearcoat       float/texture  0      strength of the clear coat lobe
 *   clearcoatGloss  float/texture  1      0: satin coat (α = 0.1), 1: gloss coat (α = 0.001)
 *   lobes           string  all     which lobes to keep, among diffuse, sheen, specular,
 *                                   clearcoat (comma-separated), to look at one alone
 *   energyConserving  boolean  false  layer the lobes by albedo scaling instead of
 *                                     adding them, so the albedo never exceeds 1
 *
 *   <bsdf type="disney"/>
 *
 *   <bsdf type="disney">
 *       <color name="baseColor" value="0.6, 0.2, 0.1"/>
 *       <float name="roughness" value="0.3"/> <float name="specularTint" value="0.5"/>
 *       <float name="sheen" value="1"/> <float name="clearcoat" value="1"/>
 *       <float name="clearcoatGloss" value="0.5"/> <float name="subsurface" value="0.5"/>
 *   </bsdf>
 *
 *   <bsdf type="disney">
 *       <color name="baseColor" value="0.9, 0.6, 0.3"/> <float name="metallic" value="1"/>
 *       <float name="roughness" value="0.4"/> <float name="anisotropic" value="0.8"/>
 *   </bsdf>
 *
 *   <bsdf type="disney">
 *       <color name="baseColor" value="0.9, 0.9, 0.85"/> <float name="roughness" value="0.6"/>
 *       <float name="sheen" value="1"/> <float name="clearcoat" value="1"/>
 *       <boolean name="energyConserving" value="true"/>
 *   </bsdf>
 *
 *   <bsdf type="disney">
 *       <texture type="checkerboard" name="baseColor">
 *           <color name="color0" value="0.1, 0.3, 0.6"/> <color name="color1" value="0.7"/>
 *       </texture>
 *       <texture type="checkerboard" name="roughness">
 *           <color name="color0" value="0.2"/> <color name="color1" value="0.8"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/albedotable.h>
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/microfacet.h>
#include <nori/proplist.h>
#include <nori/strutil.h>
#include <nori/warp.h>

#include <array>

namespace nori {
namespace {

/// Schlick's weight (1 − cos θ)⁵ (Schlick 1994, eq. 24).
float schlickWeight(float cosTheta) {
    const float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}

template <typename T> T mix(const T &a, const T &b, float t) {
    return a + (b - a) * t;
}

/// The Smith shadowing of the clear coat: GGX with α = 0.25 (Burley's smithG_GGX(·, .25)).
const MicrofacetDistribution kClearcoatShadowing(MicrofacetDistribution::Type::GGX, 0.25f);

enum Lobe { kDiffuseLobe, kSheenLobe, kSpecularLobe, kClearcoatLobe, kLobeCount };
const std::array<const char *, kLobeCount> kLobeNames = {"diffuse", "sheen", "specular",
                                                         "clearcoat"};

/// The directional albedos the layered (energyConserving) model scales by, each tabulated
/// over cos θi and the parameter named (48 × 32 nodes of 1024 samples, built at the first
/// energy-conserving Disney, in 0.26 s on 2 cores).
struct AlbedoTables {
    /// GGX specular over roughness (α = roughness², at least 0.001), with Schlick's
    /// Fresnel F = F0 (1 − FH) + FH split: E = F0·specularF0 + specularOne.
    AlbedoTable specularF0, specularOne;
    /// The clear coat at clearcoat 1, over clearcoatGloss.
    AlbedoTable clearcoat;
    /// Burley's diffuse Fd/π and the subsurface term, over roughness (white baseColor).
    AlbedoTable diffuse, subsurface;
    /// The sheen's FH at sheen 1 and white tint (one row: it has no parameter).
    AlbedoTable sheen;

    static const AlbedoTables &get();
};

/// The microfacet weight D G/(4 cos θi cos θo) · cos θo / pdf of a visible-normal sample.
float specularWeight(const MicrofacetDistribution &lobe, const Vector3f &wi, const Vector3f &wo,
                     const Vector3f &h) {
    if (Frame::cosTheta(wo) <= 0.0f)
        return 0.0f;
    const float density = lobe.pdfNormal(wi, h) / (4.0f * std::abs(h.dot(wo)));
    return density > 0.0f ? lobe.D(h) * lobe.G(wi, wo, h) / (4.0f * Frame::cosTheta(wi) * density)
                          : 0.0f;
}

/// Burley's diffuse factors Fd (retro-reflection) and the subsurface term for cosines of
/// the two directions and of θd (Burley 2012, §5.3).
std::pair<float, float> diffuseFactors(float cosI, float cosO, float cosD, float roughness) {
    const float FI = schlickWeight(cosI), FO = schlickWeight(cosO);
    const float Fd90 = 0.5f + 2.0f * cosD * cosD * roughness;
    const float Fd = mix(1.0f, Fd90, FI) * mix(1.0f, Fd90, FO);
    const float Fss90 = cosD * cosD * roughness;
    const float Fss = mix(1.0f, Fss90, FI) * mix(1.0f, Fss90, FO);
    return {Fd, 1.25f * (Fss * (1.0f / (cosI + cosO) - 0.5f) + 0.5f)};
}

const AlbedoTables &AlbedoTables::get() {
    constexpr int kAngles = 48, kParameters = 32, kSamples = 1024;
    auto specular = [](bool schlickPart) {
        return [schlickPart](const Vector3f &wi, float roughness, const Point2f &u) {
            const MicrofacetDistribution lobe(MicrofacetDistribution::Type::GGX,
                                              std::max(0.001f, roughness * roughness));
            const Vector3f h = lobe.sampleNormal(wi, u);
            const Vector3f wo = reflect(wi, h);
            const float FH = schlickWeight(h.dot(wi));
            return specularWeight(lobe, wi, wo, h) * (schlickPart ? FH : 1.0f - FH);
        };
    };
    auto cosineWeighted = [](auto &&factor) {
        return [factor](const Vector3f &wi, float p, const Point2f &u) {
            const Vector3f wo = Warp::squareToCosineHemisphere(u);
            const Vector3f h = Vector3f(wi + wo).normalized();
            // f·cos θo / (cos θo/π) = π f
            return factor(wi.z(), wo.z(), h.dot(wi), p);
        };
    };
    static const AlbedoTables tables{
        AlbedoTable(kAngles, kParameters, kSamples, specular(false)),
        AlbedoTable(kAngles, kParameters, kSamples, specular(true)),
        AlbedoTable(kAngles, kParameters, kSamples,
                    [](const Vector3f &wi, float gloss, const Point2f &u) {
                        const float alpha = mix(0.1f, 0.001f, gloss);
                        const Vector3f h = Warp::squareToGTR1(u, alpha);
                        const Vector3f wo = reflect(wi, h);
                        if (Frame::cosTheta(wo) <= 0.0f)
                            return 0.0f;
                        const float F = mix(0.04f, 1.0f, schlickWeight(h.dot(wi)));
                        // D/pdf(h) = 1/cos θh; the reflection's Jacobian 1/(4 |wo·h|).
                        return 0.25f * F * kClearcoatShadowing.G(wi, wo, h) * std::abs(h.dot(wo)) /
                               (Frame::cosTheta(wi) * h.z());
                    }),
        AlbedoTable(kAngles, kParameters, kSamples,
                    cosineWeighted([](float i, float o, float d, float r) {
                        return diffuseFactors(i, o, d, r).first;
                    })),
        AlbedoTable(kAngles, kParameters, kSamples,
                    cosineWeighted([](float i, float o, float d, float r) {
                        return diffuseFactors(i, o, d, r).second;
                    })),
        AlbedoTable(kAngles, 1, kSamples, cosineWeighted([](float, float, float d, float) {
                        return kPi * schlickWeight(d);
                    }))};
    return tables;
}

class Disney : public BSDF {
public:
    explicit Disney(const PropertyList &props) {
        if (props.has("baseColor") && props.has("albedo"))
            throw NoriException("disney: give 'baseColor' or its alias 'albedo', not both");
        m_baseColor = m_textures.color(props, props.has("albedo") ? "albedo" : "baseColor",
                                       Color3f(0.82f, 0.67f, 0.16f));
        const Color3f base = m_baseColor->average();
        if (m_baseColor->isConstant() && ((base < 0.0f).any() || (base > 1.0f).any()))
            throw NoriException("disney: 'baseColor' must lie in [0, 1], got ({}, {}, {})",
                                base.r(), base.g(), base.b());
        auto unit = [&](const char *name, float defaultValue) {
            return m_textures.scalar(props, name, defaultValue, 0.0f, 1.0f);
        };
        m_metallic = unit("metallic", 0.0f);
        m_subsurface = unit("subsurface", 0.0f);
        m_specular = unit("specular", 0.5f);
        m_specularTint = unit("specularTint", 0.0f);
        m_roughness = unit("roughness", 0.5f);
        m_anisotropic = unit("anisotropic", 0.0f);
        m_sheen = unit("sheen", 0.0f);
        m_sheenTint = unit("sheenTint", 0.0f);
        m_clearcoat = unit("clearcoat", 0.0f);
        m_clearcoatGloss = unit("clearcoatGloss", 1.0f);
        readLobes(props.getString("lobes", "all"));
        m_energyConserving = props.getBoolean("energyConserving", false);
        if (m_energyConserving)
            AlbedoTables::get(); // build the tables at load time, not in the first pixel
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        return isFrontReflection(bRec) ? evalAt(materialAt(bRec), bRec) : Color3f(0.0f);
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        return isFrontReflection(bRec) ? pdfAt(materialAt(bRec), bRec) : 0.0f;
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        // The textures are looked up once, for the choice, the value and the density.
        const Material mat = materialAt(bRec);
        // Pick a strategy with the first coordinate and rescale it to [0, 1) for reuse.
        float u = sample.x();
        int strategy = 0;
        while (strategy < 2 && u >= mat.selection[strategy]) {
            u -= mat.selection[strategy];
            ++strategy;
        }
        if (mat.selection[strategy] == 0.0f)
            return Color3f(0.0f); // every lobe is off here
        const Point2f reused(std::clamp(u / mat.selection[strategy], 0.0f, 1.0f - 1e-7f),
                             sample.y());
        if (strategy == 0)
            bRec.wo = Warp::squareToCosineHemisphere(reused);
        else if (strategy == 1)
            bRec.wo = reflect(bRec.wi, mat.specularLobe.sampleNormal(bRec.wi, reused));
        else
            bRec.wo = reflect(bRec.wi, Warp::squareToGTR1(reused, mat.clearcoatAlpha));
        if (Frame::cosTheta(bRec.wo) <= 0.0f)
            return Color3f(0.0f);
        // eval·cos θo/pdf, as BSDF::sampleWeight computes it, from this material.
        const float density = pdfAt(mat, bRec);
        return density > 0.0f ? Color3f(evalAt(mat, bRec) * (Frame::cosTheta(bRec.wo) / density))
                              : Color3f(0.0f);
    }

    bool isDiffuse() const override { return true; }

    std::string toString() const override {
        std::string lobes;
        for (int lobe = 0; lobe < kLobeCount; ++lobe)
            if (m_enabled[lobe])
                lobes += (lobes.empty() ? "" : "+") + std::string(kLobeNames[lobe]);
        return fmt::format(
            "Disney[baseColor={}, metallic={}, subsurface={}, specular={}, specularTint={}, "
            "roughness={}, anisotropic={}, sheen={}, sheenTint={}, clearcoat={}, "
            "clearcoatGloss={}, lobes={}, energyConserving={}]",
            m_baseColor->toString(), m_metallic->toString(), m_subsurface->toString(),
            m_specular->toString(), m_specularTint->toString(), m_roughness->toString(),
            m_anisotropic->toString(), m_sheen->toString(), m_sheenTint->toString(),
            m_clearcoat->toString(), m_clearcoatGloss->toString(), lobes, m_energyConserving);
    }

private:
    /// The parameters at one point, with what the lobes derive from them.
    struct Material {
        Color3f baseColor, specularColor, sheenColor;
        float metallic, subsurface, roughness, sheen, clearcoat, clearcoatGloss, clearcoatAlpha;
        MicrofacetDistribution specularLobe;
        /// Probabilities of the sampling strategies: cosine (diffuse and sheen), GTR2, GTR1.
        std::array<float, 3> selection;
    };

    /// f for wi and wo both above the surface.
    Color3f evalAt(const Material &mat, const BSDFQueryRecord &bRec) const {
        const std::array<Color3f, kLobeCount> f = lobeValues(mat, bRec);
        if (!m_energyConserving)
            return f[kDiffuseLobe] + f[kSheenLobe] + f[kSpecularLobe] + f[kClearcoatLobe];
        return layered(mat, f, Frame::cosTheta(bRec.wi), Frame::cosTheta(bRec.wo));
    }

    /// Each lobe's f as Burley adds them (the lobes that are off: 0).
    std::array<Color3f, kLobeCount> lobeValues(const Material &mat,
                                               const BSDFQueryRecord &bRec) const {
        const float cosI = Frame::cosTheta(bRec.wi), cosO = Frame::cosTheta(bRec.wo);
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        const float cosD = h.dot(bRec.wi); // θd, the angle of either direction to h
        const float FH = schlickWeight(cosD);
        std::array<Color3f, kLobeCount> f;
        f.fill(Color3f(0.0f));
        if (m_enabled[kDiffuseLobe]) {
            // Burley 2012, §5.3: retro-reflection through Fd90, and the subsurface
            // flattening Fss with its 1/(cos θi + cos θo) − 1/2 volume term.
            const auto [Fd, ss] = diffuseFactors(cosI, cosO, cosD, mat.roughness);
            f[kDiffuseLobe] =
                mat.baseColor * (kInvPi * mix(Fd, ss, mat.subsurface) * (1.0f - mat.metallic));
        }
        if (m_enabled[kSheenLobe])
            f[kSheenLobe] = mat.sheenColor * (FH * mat.sheen * (1.0f - mat.metallic));
        if (m_enabled[kSpecularLobe]) {
            const Color3f F = mix(mat.specularColor, Color3f(1.0f), FH);
            f[kSpecularLobe] = F * (mat.specularLobe.D(h) *
                                    mat.specularLobe.G(bRec.wi, bRec.wo, h) / (4.0f * cosI * cosO));
        }
        if (m_enabled[kClearcoatLobe] && mat.clearcoat > 0.0f) {
            const float D = Warp::squareToGTR1Pdf(h, mat.clearcoatAlpha) / h.z();
            const float F = mix(0.04f, 1.0f, FH);
            f[kClearcoatLobe] =
                Color3f(0.25f * mat.clearcoat * D * F * kClearcoatShadowing.G(bRec.wi, bRec.wo, h) /
                        (4.0f * cosI * cosO));
        }
        return f;
    }

    /// The lobes layered by albedo scaling (Kulla & Conty 2017): clearcoat over specular
    /// over sheen over diffuse, f = f_c + S_c (f_s + S_s (f_sh + S_sh f_d)) with
    /// S(θi, θo) = (1 − E(θi))(1 − E(θo)) for E the directional albedo of the layer above.
    /// Then the albedo for either direction is at most E_c + (1 − E_c)(E_s + (1 − E_s)
    /// (E_sh + (1 − E_sh) E_d)) ≤ 1, because every factor 1 − E(θ) of the other direction
    /// is at most 1; and S is symmetric, so f stays reciprocal.
    Color3f layered(const Material &mat, const std::array<Color3f, kLobeCount> &f, float cosI,
                    float cosO) const {
        const AlbedoTables &tables = AlbedoTables::get();
        auto scale = [&](auto &&albedo) -> Color3f {
            const Color3f below = (Color3f(1.0f) - albedo(cosI)).max(0.0f);
            return below * (Color3f(1.0f) - albedo(cosO)).max(0.0f);
        };
        // The diffuse and sheen lobes divided by their largest albedo where it exceeds 1.
        const float diffuseLargest =
            mix(tables.diffuse.maxOverMu(mat.roughness), tables.subsurface.maxOverMu(mat.roughness),
                mat.subsurface);
        const Color3f diffuse = f[kDiffuseLobe] / std::max(1.0f, diffuseLargest);
        const Color3f sheenAlbedo = mat.sheenColor * (mat.sheen * (1.0f - mat.metallic));
        const Color3f sheenScale =
            Color3f(1.0f) / (sheenAlbedo * tables.sheen.maxOverMu()).max(1.0f);
        const Color3f sheen = f[kSheenLobe] * sheenScale;
        Color3f result = diffuse;
        if (m_enabled[kSheenLobe])
            result = sheen + result * scale([&](float mu) {
                                 return Color3f(sheenAlbedo * sheenScale * tables.sheen(mu));
                             });
        if (m_enabled[kSpecularLobe]) {
            // The table's roughness for an anisotropic lobe: the geometric mean of its α.
            const float roughness =
                std::sqrt(std::sqrt(mat.specularLobe.alphaX() * mat.specularLobe.alphaY()));
            result = f[kSpecularLobe] +
                     result * scale([&](float mu) {
                         return Color3f(mat.specularColor * tables.specularF0(mu, roughness) +
                                        Color3f(tables.specularOne(mu, roughness)));
                     });
        }
        if (m_enabled[kClearcoatLobe])
            result = f[kClearcoatLobe] +
                     result * scale([&](float mu) {
                         return Color3f(mat.clearcoat * tables.clearcoat(mu, mat.clearcoatGloss));
                     });
        return result;
    }

    /// The density of sample() for wi and wo both above the surface.
    float pdfAt(const Material &mat, const BSDFQueryRecord &bRec) const {
        const Vector3f h = Vector3f(bRec.wi + bRec.wo).normalized();
        // A reflected direction's density is its half vector's density times the
        // Jacobian 1/(4 |wo·h|) (Walter et al. 2007, eq. 14).
        const float jacobian = 1.0f / (4.0f * std::abs(h.dot(bRec.wo)));
        float density = 0.0f;
        if (mat.selection[0] > 0.0f)
            density += mat.selection[0] * Warp::squareToCosineHemispherePdf(bRec.wo);
        if (mat.selection[1] > 0.0f)
            density += mat.selection[1] * mat.specularLobe.pdfNormal(bRec.wi, h) * jacobian;
        if (mat.selection[2] > 0.0f)
            density += mat.selection[2] * Warp::squareToGTR1Pdf(h, mat.clearcoatAlpha) * jacobian;
        return density;
    }

    Material materialAt(const TextureQuery &q) const {
        auto unit = [&q](const std::shared_ptr<const Texture> &t) {
            return std::clamp(t->evalFloat(q), 0.0f, 1.0f);
        };
        const Color3f base = m_baseColor->eval(q).max(0.0f).min(1.0f);
        const float metallic = unit(m_metallic), roughness = unit(m_roughness);
        // The hue of baseColor at unit luminance (Burley's Ctint, luminance .3/.6/.1).
        const float luminance = 0.3f * base.r() + 0.6f * base.g() + 0.1f * base.b();
        const Color3f tint = luminance > 0.0f ? Color3f(base / luminance) : Color3f(1.0f);
        const Color3f specularColor =
            mix(Color3f(0.08f * unit(m_specular) * mix(Color3f(1.0f), tint, unit(m_specularTint))),
                base, metallic);
        const float aspect = std::sqrt(1.0f - 0.9f * unit(m_anisotropic));
        const float r2 = roughness * roughness;
        const MicrofacetDistribution specularLobe(MicrofacetDistribution::Type::GGX,
                                                  std::max(0.001f, r2 / aspect),
                                                  std::max(0.001f, r2 * aspect));
        const float clearcoat = unit(m_clearcoat), gloss = unit(m_clearcoatGloss);
        std::array<float, 3> weights = {
            m_enabled[kDiffuseLobe] || m_enabled[kSheenLobe] ? 1.0f - metallic : 0.0f,
            m_enabled[kSpecularLobe] ? 1.0f : 0.0f,
            m_enabled[kClearcoatLobe] ? 0.25f * clearcoat : 0.0f};
        const float total = weights[0] + weights[1] + weights[2];
        for (float &w : weights)
            w = total > 0.0f ? w / total : 0.0f;
        return {base,
                specularColor,
                mix(Color3f(1.0f), tint, unit(m_sheenTint)),
                metallic,
                unit(m_subsurface),
                roughness,
                unit(m_sheen),
                clearcoat,
                gloss,
                mix(0.1f, 0.001f, gloss),
                specularLobe,
                weights};
    }

    void readLobes(const std::string &list) {
        if (list == "all") {
            m_enabled.fill(true);
            return;
        }
        m_enabled.fill(false);
        const std::vector<std::string> names(kLobeNames.begin(), kLobeNames.end());
        for (const std::string &name : tokenize(list)) {
            const auto found = std::find(names.begin(), names.end(), name);
            if (found == names.end())
                throw NoriException("disney: unknown lobe '{}' in 'lobes'{} (use 'all' or some "
                                    "of diffuse, sheen, specular, clearcoat)",
                                    name, didYouMean(name, names));
            m_enabled[found - names.begin()] = true;
        }
        if (std::find(m_enabled.begin(), m_enabled.end(), true) == m_enabled.end())
            throw NoriException("disney: 'lobes' names no lobe");
    }

    std::shared_ptr<const Texture> m_baseColor, m_metallic, m_subsurface, m_specular,
        m_specularTint, m_roughness, m_anisotropic, m_sheen, m_sheenTint, m_clearcoat,
        m_clearcoatGloss;
    std::array<bool, kLobeCount> m_enabled{};
    bool m_energyConserving = false;
};

NORI_REGISTER_CLASS(Disney, "disney");

} // namespace
} // namespace nori
