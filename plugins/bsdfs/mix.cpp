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
#include <nori/bsdf.h>
#include <nori/hash.h>

namespace nori {
namespace {

class Mix : public BSDF {
public:
    explicit Mix(const PropertyList &props) {
        m_amount = m_textures.scalar(props, "amount", 0.5f, 0.0f, 1.0f);
    }

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() != EBSDF)
            return BSDF::addChild(child, name);
        if (m_bsdfs[1])
            throw NoriException("mix: takes exactly two nested BSDFs, got a third");
        (m_bsdfs[0] ? m_bsdfs[1] : m_bsdfs[0]) = std::static_pointer_cast<BSDF>(child);
    }

    void activate() override {
        if (!m_bsdfs[1])
            throw NoriException("mix: needs two nested <bsdf>s, got {}", m_bsdfs[0] ? 1 : 0);
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return chosen(bRec).sample(bRec, sample);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return chosen(bRec).eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return chosen(bRec).pdf(bRec); }
    bool isDiffuse() const override { return m_bsdfs[0]->isDiffuse() || m_bsdfs[1]->isDiffuse(); }
    Color3f albedo(const BSDFQueryRecord &bRec) const override { return chosen(bRec).albedo(bRec); }
    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        return chosen(bRec).discreteLobes(bRec, lobes);
    }

    std::string toString() const override {
        return fmt::format("Mix[amount={}, {}, {}]", m_amount->toString(),
                           m_bsdfs[0] ? m_bsdfs[0]->toString() : "",
                           m_bsdfs[1] ? m_bsdfs[1]->toString() : "");
    }

private:
    /// The BSDF at the query's point: the second where a uniform number hashed from the
    /// point's coordinates falls below the amount (pbrt-v4: amount < u keeps the first).
    const BSDF &chosen(const BSDFQueryRecord &bRec) const {
        const float amount = m_amount->evalFloat(bRec);
        if (amount <= 0.0f)
            return *m_bsdfs[0];
        if (amount >= 1.0f)
            return *m_bsdfs[1];
        const float u = hashToUnitFloat(hashFloats(bRec.p.x(), bRec.p.y(), bRec.p.z()));
        return amount < u ? *m_bsdfs[0] : *m_bsdfs[1];
    }

    std::shared_ptr<const Texture> m_amount;
    std::shared_ptr<BSDF> m_bsdfs[2];
};

NORI_REGISTER_CLASS(Mix, "mix");

} // namespace
} // namespace nori
