/*
 * diffusetransmission — a thin diffuse sheet that reflects and transmits, both
 * Lambertian, from either side: paper, a leaf, a lampshade (pbrt-v4's
 * DiffuseTransmissionBxDF; PBR 4th ed. §9.2 and the `diffusetransmission` material):
 * f = R/π toward wi's side and T/π toward the other. Samples the reflecting side with
 * probability max(R)/(max(R) + max(T)), then a cosine-weighted direction.
 *
 * Parameters:
 *   reflectance    color/texture  0.25  fraction reflected, per channel
 *   transmittance  color/texture  0.25  fraction transmitted, per channel
 *   scale          float          1     multiplies both (pbrt-v4's); the products are
 *                                       clamped to [0, 1], and a sum over 1 warns
 *
 *   <bsdf type="diffusetransmission"/>
 *
 *   <bsdf type="diffusetransmission">
 *       <color name="reflectance" value="0.3, 0.5, 0.2"/>
 *       <color name="transmittance" value="0.5, 0.4, 0.1"/>
 *   </bsdf>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/warp.h>

#include <iostream>

namespace nori {
namespace {

class DiffuseTransmission : public BSDF {
public:
    explicit DiffuseTransmission(const PropertyList &props) {
        m_reflectance = m_textures.color(props, "reflectance", Color3f(0.25f));
        m_transmittance = m_textures.color(props, "transmittance", Color3f(0.25f));
        m_scale = props.getFloat("scale", 1.0f);
        if (!(m_scale >= 0.0f))
            throw NoriException("diffusetransmission: 'scale' must not be negative, got {}",
                                m_scale);
        const float reflectMax = m_reflectance->average().maxCoeff() * m_scale,
                    transmitMax = m_transmittance->average().maxCoeff() * m_scale;
        if (m_reflectance->isConstant() && m_transmittance->isConstant() &&
            (reflectMax + transmitMax > 1.0f + 1e-6f))
            std::cerr << fmt::format("Warning: diffusetransmission: reflectance + transmittance "
                                     "exceed 1 ({} + {}): more light leaves than arrives\n",
                                     reflectMax, transmitMax);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosI = Frame::cosTheta(bRec.wi);
        if (cosI == 0.0f)
            return Color3f(0.0f);
        const Color3f R = reflectance(bRec), T = transmittance(bRec);
        const float reflectProbability = reflectionProbability(R, T);
        if (!(reflectProbability >= 0.0f)) // neither side: nothing to sample
            return Color3f(0.0f);
        bRec.measure = ESolidAngle;
        bRec.eta = 1.0f;
        const bool reflect = sample.x() < reflectProbability;
        const Point2f reused(reflect
                                 ? sample.x() / reflectProbability
                                 : (sample.x() - reflectProbability) / (1.0f - reflectProbability),
                             sample.y());
        bRec.wo = Warp::squareToCosineHemisphere(reused);
        // wo on wi's side for reflection, on the other for transmission.
        if ((cosI < 0.0f) == reflect)
            bRec.wo.z() = -bRec.wo.z();
        if (Frame::cosTheta(bRec.wo) == 0.0f)
            return Color3f(0.0f);
        // f·|cos|/pdf = (R/π)|cos| / (P |cos|/π) = R/P, and T/(1 − P) for transmission.
        return reflect ? Color3f(R / reflectProbability) : Color3f(T / (1.0f - reflectProbability));
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) == 0.0f ||
            Frame::cosTheta(bRec.wo) == 0.0f)
            return Color3f(0.0f);
        const bool sameSide = Frame::cosTheta(bRec.wi) * Frame::cosTheta(bRec.wo) > 0.0f;
        return (sameSide ? reflectance(bRec) : transmittance(bRec)) * kInvPi;
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (bRec.measure != ESolidAngle || Frame::cosTheta(bRec.wi) == 0.0f ||
            Frame::cosTheta(bRec.wo) == 0.0f)
            return 0.0f;
        const float reflectProbability =
            reflectionProbability(reflectance(bRec), transmittance(bRec));
        if (!(reflectProbability >= 0.0f))
            return 0.0f;
        const bool sameSide = Frame::cosTheta(bRec.wi) * Frame::cosTheta(bRec.wo) > 0.0f;
        return (sameSide ? reflectProbability : 1.0f - reflectProbability) *
               std::abs(Frame::cosTheta(bRec.wo)) * kInvPi;
    }

    bool isDiffuse() const override { return true; }

    /// R + T from either side.
    Color3f albedo(const BSDFQueryRecord &bRec) const override {
        return Frame::cosTheta(bRec.wi) != 0.0f ? Color3f(reflectance(bRec) + transmittance(bRec))
                                                : Color3f(0.0f);
    }

    std::string toString() const override {
        return fmt::format("DiffuseTransmission[reflectance={}, transmittance={}, scale={}]",
                           m_reflectance->toString(), m_transmittance->toString(), m_scale);
    }

private:
    Color3f reflectance(const TextureQuery &q) const {
        return (m_reflectance->eval(q) * m_scale).max(0.0f).min(1.0f);
    }
    Color3f transmittance(const TextureQuery &q) const {
        return (m_transmittance->eval(q) * m_scale).max(0.0f).min(1.0f);
    }

    /// pbrt-v4's choice of side: max(R)/(max(R) + max(T)); −1 when both are black.
    static float reflectionProbability(const Color3f &R, const Color3f &T) {
        const float pr = R.maxCoeff(), pt = T.maxCoeff();
        return pr + pt > 0.0f ? pr / (pr + pt) : -1.0f;
    }

    std::shared_ptr<const Texture> m_reflectance, m_transmittance;
    float m_scale;
};

NORI_REGISTER_CLASS(DiffuseTransmission, "diffusetransmission");

} // namespace
} // namespace nori
