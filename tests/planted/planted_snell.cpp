/*
 * planted_snell — a negative control: a smooth dielectric (glass) that refracts with
 * η_i/η_t where Snell's law needs η_t/η_i. Purely discrete, so no χ² test applies; the
 * check of the discrete law must reject it.
 *
 * No parameters.
 *
 *   <bsdf type="planted_snell"/>
 */
#include <nori/bsdf.h>
#include <nori/frame.h>
#include <nori/fresnel.h>

namespace nori {

class PlantedSnell : public BSDF {
public:
    explicit PlantedSnell(const PropertyList &) {}

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float cosThetaI = Frame::cosTheta(bRec.wi);
        const float fresnel = fresnelDielectric(cosThetaI, 1.0f, 1.5f);
        bRec.measure = EDiscrete;
        if (sample.x() < fresnel) {
            bRec.wo = Vector3f(-bRec.wi.x(), -bRec.wi.y(), bRec.wi.z());
            bRec.eta = 1.0f;
            return Color3f(1.0f);
        }
        const bool outside = cosThetaI > 0.0f;
        const float eta = outside ? 1.5f : 1.0f / 1.5f;
        const Vector3f normal(0.0f, 0.0f, outside ? 1.0f : -1.0f);
        if (!refract(bRec.wi, normal, 1.0f / eta, bRec.wo)) // the planted bug: 1/eta
            return Color3f(0.0f);
        bRec.eta = eta;
        return Color3f(1.0f / (eta * eta));
    }
    Color3f eval(const BSDFQueryRecord &) const override { return Color3f(0.0f); }
    float pdf(const BSDFQueryRecord &) const override { return 0.0f; }
    std::string toString() const override { return "PlantedSnell[]"; }
};

NORI_REGISTER_CLASS(PlantedSnell, "planted_snell");

} // namespace nori
