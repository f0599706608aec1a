/*
 * conductor — a smooth metal: specular reflection weighted by the conductor Fresnel
 * term (PBR 4th ed. §9.3.6).
 *
 * Parameters:
 *   material  string  —                  a named metal: Au, Ag, Cu, Al, Cr, CuZn, W, none, …
 *                                        (every name of Mitsuba 0.6 and pbrt-v4; instead of eta, k)
 *   eta       color/texture  (0.2, 0.92, 1.1)   real part of the index of refraction (copper)
 *   k         color/texture  (3.9, 2.45, 2.14)  imaginary part (absorption)
 *   extIOR    float   1.000277           index of refraction of the outside
 *
 *   <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
 */
#include <nori/bsdf.h>
#include <nori/bsdfparams.h>
#include <nori/frame.h>
#include <nori/fresnel.h>

namespace nori {
namespace {

class Conductor : public BSDF {
public:
    explicit Conductor(const PropertyList &props) {
        m_ior = readConductorIOR(props, "conductor", m_textures);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &) const override {
        const float cosThetaI = Frame::cosTheta(bRec.wi);
        if (cosThetaI <= 0.0f)
            return Color3f(0.0f);
        bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
        bRec.measure = EDiscrete;
        bRec.eta = 1.0f;
        return m_ior.fresnel(bRec, cosThetaI);
    }

    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }

    std::string toString() const override {
        return fmt::format("Conductor[eta={}, k={}, extIOR={}]", m_ior.eta->toString(),
                           m_ior.k->toString(), m_ior.extIOR);
    }

private:
    ConductorIOR m_ior;
};

NORI_REGISTER_CLASS(Conductor, "conductor");

} // namespace
} // namespace nori
