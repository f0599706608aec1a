/*
 * blendbsdf — a linear blend of two BSDFs, f = (1 − w) f₀ + w f₁, with w a weight that may
 * be a texture (Mitsuba 0.6 documentation, "blendbsdf"): the mean of its channels,
 * clamped to [0, 1]. Samples the second BSDF with probability w and the first otherwise;
 * a smooth sample is weighted by the blend's own eval and pdf (the one-sample MIS of the
 * two), a discrete one by its lobe's weight.
 *
 * Parameters:
 *   weight  float/texture  0.5  how much of the second nested BSDF, in [0, 1]
 *
 * Children: two nested <bsdf>s, the first and the second.
 *
 *   <bsdf type="blendbsdf"><float name="weight" value="0.3"/>
 *       <bsdf type="diffuse"><color name="albedo" value="0.8, 0.2, 0.2"/></bsdf>
 *       <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf>
 *   </bsdf>
 *
 *   <bsdf type="blendbsdf"><float name="weight" value="0.6"/>
 *       <bsdf type="dielectric"/> <bsdf type="diffuse"/>
 *   </bsdf>
 */
#include <nori/frame.h>
#include <nori/nestedbsdf.h>

namespace nori {
namespace {

class BlendBSDF : public NestedBSDF {
public:
    explicit BlendBSDF(const PropertyList &props) : NestedBSDF("blendbsdf", 2, 2) {
        m_weight = m_textures.scalar(props, "weight", 0.5f, 0.0f, 1.0f);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const float w = weight(bRec);
        const int chosen = sample.x() < w ? 1 : 0;
        const Point2f reused(chosen == 1 ? sample.x() / w : (sample.x() - w) / (1.0f - w),
                             sample.y());
        Color3f lobeWeight = nested(static_cast<size_t>(chosen)).sample(bRec, reused);
        if ((lobeWeight == 0.0f).all())
            return Color3f(0.0f);
        // A Dirac lobe of the chosen BSDF (chosen with probability P): the blend's lobe has
        // probability P·p and weight P·(weight·p), so its sample weight is the lobe's own.
        if (bRec.measure == EDiscrete)
            return lobeWeight;
        return sampleWeight(bRec);
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        const float w = weight(bRec);
        return nested(0).eval(bRec) * (1.0f - w) + nested(1).eval(bRec) * w;
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        const float w = weight(bRec);
        return (1.0f - w) * nested(0).pdf(bRec) + w * nested(1).pdf(bRec);
    }

    bool isDiffuse() const override { return anyNestedDiffuse(); }

    Color3f albedo(const BSDFQueryRecord &bRec) const override {
        const float w = weight(bRec);
        return nested(0).albedo(bRec) * (1.0f - w) + nested(1).albedo(bRec) * w;
    }

    std::string toString() const override {
        return fmt::format("BlendBSDF[weight={}, {}]", m_weight->toString(), nestedToString());
    }

private:
    /// Mitsuba's weight: the mean of the texture's channels, clamped to [0, 1].
    float weight(const TextureQuery &q) const {
        return std::clamp(m_weight->eval(q).mean(), 0.0f, 1.0f);
    }

    std::shared_ptr<const Texture> m_weight;
};

NORI_REGISTER_CLASS(BlendBSDF, "blendbsdf");

} // namespace
} // namespace nori
