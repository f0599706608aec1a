/*
 * diffuse — an ideal Lambertian reflector (PBR 4th ed. §9.2).
 *
 * Parameters:
 *   albedo  color/texture  0.5  fraction of light reflected, per channel, in [0, 1]
 *                               (texture values are clamped to [0, 1])
 *
 *   <bsdf type="diffuse">
 *       <color name="albedo" value="0.7, 0.2, 0.2"/>
 *   </bsdf>
 *
 *   <bsdf type="diffuse">
 *       <texture type="checkerboard" name="albedo">
 *           <color name="color0" value="0.1"/> <color name="color1" value="0.8"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

namespace nori {
namespace {

class Diffuse : public BSDF {
public:
    explicit Diffuse(const PropertyList &props) {
        m_albedo = m_textures.color(props, "albedo", Color3f(0.5f));
        const Color3f mean = m_albedo->average();
        if (m_albedo->isConstant() && ((mean < 0.0f).any() || (mean > 1.0f).any()))
            throw NoriException("diffuse: 'albedo' must lie in [0, 1], got ({}, {}, {})", mean.r(),
                                mean.g(), mean.b());
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        if (Frame::cosTheta(bRec.wi) <= 0.0f)
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.wo = Warp::squareToCosineHemisphere(sample);
        bRec.eta = 1.0f;
        // eval·cos/pdf = (albedo/π)·cos / (cos/π) = albedo.
        return reflectance(bRec);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return Color3f(0.0f);
        return reflectance(bRec) * kInvPi;
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (!isFrontReflection(bRec))
            return 0.0f;
        return Warp::squareToCosineHemispherePdf(bRec.wo);
    }

    bool isDiffuse() const override { return true; }

    /// A Lambertian surface reflects the fraction `albedo` of light from any direction
    /// of its front side.
    Color3f albedo(const BSDFQueryRecord &bRec) const override {
        return Frame::cosTheta(bRec.wi) > 0.0f ? reflectance(bRec) : Color3f(0.0f);
    }

    std::string toString() const override {
        return fmt::format("Diffuse[albedo={}]", m_albedo->toString());
    }

private:
    Color3f reflectance(const TextureQuery &q) const {
        return m_albedo->eval(q).max(0.0f).min(1.0f);
    }

    std::shared_ptr<const Texture> m_albedo;
};

NORI_REGISTER_CLASS(Diffuse, "diffuse");

} // namespace
} // namespace nori
