/*
 * mix — one of two BSDFs at each point, the second with probability `amount`, as pbrt-v4's
 * MixMaterial chooses (PBR 4th ed. §10.5, pbrt-v4's `mix` material): not a blend of the
 * two but a stochastic choice per point, fixed by a hash of the point, so that every query
 * there (camera path, light sample, photon) sees the same BSDF. pbrt-v4 also hashes the
 * viewing direction; this hashes the point only, which keeps the BSDF reciprocal and
 * gives the same expected image. Amounts of 0 and 1 choose without a hash.
 *
 * Parameters:
 *   amount  float/texture  0.5  the probability of the second nested BSDF, in [0, 1]
 *
 * Children: two nested <bsdf>s, the first and the second.
 *
 *   <bsdf type="mix"><float name="amount" value="0.25"/>
 *       <bsdf type="diffuse"><color name="albedo" value="0.2, 0.6, 0.2"/></bsdf>
 *       <bsdf type="roughconductor"><float name="alpha" value="0.1"/></bsdf>
 *   </bsdf>
 */
#include <nori/hash.h>
#include <nori/nestedbsdf.h>

namespace nori {
namespace {

class Mix : public NestedBSDF {
public:
    explicit Mix(const PropertyList &props) : NestedBSDF("mix", 2, 2) {
        m_amount = m_textures.scalar(props, "amount", 0.5f, 0.0f, 1.0f);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return chosen(bRec).sample(bRec, sample);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return chosen(bRec).eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return chosen(bRec).pdf(bRec); }
    bool isDiffuse() const override { return anyNestedDiffuse(); }
    Color3f albedo(const BSDFQueryRecord &bRec) const override { return chosen(bRec).albedo(bRec); }
    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        return chosen(bRec).discreteLobes(bRec, lobes);
    }

    std::string toString() const override {
        return fmt::format("Mix[amount={}, {}]", m_amount->toString(), nestedToString());
    }

private:
    /// The BSDF at the query's point: the second where a uniform number hashed from the
    /// point's coordinates falls below the amount (pbrt-v4: amount < u keeps the first).
    const BSDF &chosen(const BSDFQueryRecord &bRec) const {
        const float amount = m_amount->evalFloat(bRec);
        if (amount <= 0.0f)
            return nested(0);
        if (amount >= 1.0f)
            return nested(1);
        const float u = hashToUnitFloat(hashFloats(bRec.p.x(), bRec.p.y(), bRec.p.z()));
        return amount < u ? nested(0) : nested(1);
    }

    std::shared_ptr<const Texture> m_amount;
};

NORI_REGISTER_CLASS(Mix, "mix");

} // namespace
} // namespace nori
