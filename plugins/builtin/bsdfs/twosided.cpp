/*
 * twosided — makes a one-sided reflecting BSDF reflect on both sides (Mitsuba 0.6
 * documentation, "twosided"): seen from behind (wi.z < 0), the surface answers as the
 * nested BSDF does for the mirrored directions (wi.z and wo.z negated). With two nested
 * BSDFs, the first is the front and the second the back. Light never crosses it, so a
 * nested BSDF that transmits (dielectric, ...) is refused.
 *
 * No parameters: one or two nested <bsdf> children.
 *
 *   <bsdf type="twosided"><bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf></bsdf>
 *
 *   <bsdf type="twosided">
 *       <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf>
 *       <bsdf type="diffuse"><color name="albedo" value="0.2, 0.5, 0.2"/></bsdf>
 *   </bsdf>
 */
#include <nori/frame.h>
#include <nori/nestedbsdf.h>

namespace nori {
namespace {

class TwoSided : public NestedBSDF {
public:
    explicit TwoSided(const PropertyList &) : NestedBSDF("twosided", 1, 2) {}

    void activate() override {
        NestedBSDF::activate();
        m_front = &nested(0);
        m_back = &nested(nestedCount() - 1);
        for (const BSDF *side : {m_front, m_back})
            if (transmits(*side))
                throw NoriException("twosided: the nested {} lets light through; twosided "
                                    "takes reflecting BSDFs only",
                                    side->toString());
    }

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        const bool back = Frame::cosTheta(bRec.wi) < 0.0f;
        if (!back)
            return m_front->sample(bRec, sample);
        BSDFQueryRecord mirrored = bRec;
        mirrored.wi = flip(bRec.wi);
        Color3f weight = m_back->sample(mirrored, sample);
        // A direction on the horizon (cos θ = 0) flips to −0, below it: no sample.
        if (Frame::cosTheta(mirrored.wo) <= 0.0f)
            return Color3f(0.0f);
        bRec.wo = flip(mirrored.wo);
        bRec.eta = mirrored.eta;
        bRec.measure = mirrored.measure;
        return weight;
    }

    Color3f eval(const BSDFQueryRecord &bRec) const override {
        if (Frame::cosTheta(bRec.wi) >= 0.0f)
            return m_front->eval(bRec);
        return m_back->eval(mirror(bRec));
    }

    float pdf(const BSDFQueryRecord &bRec) const override {
        if (Frame::cosTheta(bRec.wi) >= 0.0f)
            return m_front->pdf(bRec);
        return m_back->pdf(mirror(bRec));
    }

    bool isDiffuse() const override { return anyNestedDiffuse(); }

    Color3f albedo(const BSDFQueryRecord &bRec) const override {
        if (Frame::cosTheta(bRec.wi) >= 0.0f)
            return m_front->albedo(bRec);
        return m_back->albedo(mirror(bRec));
    }

    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        if (Frame::cosTheta(bRec.wi) >= 0.0f)
            return m_front->discreteLobes(bRec, lobes);
        const int count = m_back->discreteLobes(mirror(bRec), lobes);
        for (int i = 0; i < count; ++i)
            lobes[i].wo = flip(lobes[i].wo);
        return count;
    }

    std::string toString() const override { return fmt::format("TwoSided[{}]", nestedToString()); }

private:
    static Vector3f flip(const Vector3f &w) { return {w.x(), w.y(), -w.z()}; }

    static BSDFQueryRecord mirror(const BSDFQueryRecord &bRec) {
        BSDFQueryRecord mirrored = bRec;
        mirrored.wi = flip(bRec.wi);
        mirrored.wo = flip(bRec.wo);
        return mirrored;
    }

    /// Whether the BSDF sends light from above to below: probed with a few samples from
    /// the front at several angles (a reflecting BSDF never does).
    static bool transmits(const BSDF &bsdf) {
        for (const float cosTheta : {0.9f, 0.5f, 0.1f})
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) {
                    BSDFQueryRecord bRec(
                        Vector3f(std::sqrt(1.0f - cosTheta * cosTheta), 0.0f, cosTheta));
                    const Color3f weight =
                        bsdf.sample(bRec, Point2f((i + 0.5f) / 4.0f, (j + 0.5f) / 4.0f));
                    if (!(weight == 0.0f).all() && Frame::cosTheta(bRec.wo) < 0.0f)
                        return true;
                }
        return false;
    }

    const BSDF *m_front = nullptr, *m_back = nullptr; ///< the nested ones, set by activate()
};

NORI_REGISTER_CLASS(TwoSided, "twosided");

} // namespace
} // namespace nori
