// BSDFs built around other BSDFs, given as nested <bsdf> children (Mitsuba's twosided,
// blendbsdf, mask and bumpmap; pbrt-v4's mix): the nested BSDFs are collected and counted
// here, so that each plugin says only how many it takes and what it does with them.
#pragma once

#include <nori/bsdf.h>

#include <vector>

namespace nori {

class Shape;

/// A BSDF of between `minimum` and `maximum` nested BSDFs.
class NestedBSDF : public BSDF {
public:
    /// Takes nested BSDFs, up to the maximum; other children as BSDF does.
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Checks that there are at least `minimum` nested BSDFs.
    void activate() override;

protected:
    /// `plugin` names the BSDF in errors.
    NestedBSDF(std::string plugin, size_t minimum, size_t maximum);

    size_t nestedCount() const { return m_nested.size(); }
    const BSDF &nested(size_t i) const { return *m_nested[i]; }
    const std::shared_ptr<BSDF> &nestedPtr(size_t i) const { return m_nested[i]; }
    /// Adds a nested BSDF as a child would (a default one, say).
    void addNested(std::shared_ptr<BSDF> bsdf);
    /// Whether any nested BSDF is not a delta distribution.
    bool anyNestedDiffuse() const;
    /// The nested BSDFs' toString(), comma-separated.
    std::string nestedToString() const;

    const std::string &plugin() const { return m_plugin; }

private:
    std::string m_plugin;
    size_t m_minimum, m_maximum;
    std::vector<std::shared_ptr<BSDF>> m_nested;
};

/// A BSDF that scatters as its one nested BSDF does and gives the shape it is attached to
/// something more (Mitsuba's mask: an alpha mask; bumpmap: a bump map): attached to a
/// shape, it decorates the shape and attaches the nested BSDF in its place.
class SurfaceWrapperBSDF : public NestedBSDF {
public:
    bool attachTo(NoriObject &parent, const std::string &name) override;

    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return nested(0).sample(bRec, sample);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return nested(0).eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return nested(0).pdf(bRec); }
    bool isDiffuse() const override { return nested(0).isDiffuse(); }
    Color3f albedo(const BSDFQueryRecord &bRec) const override { return nested(0).albedo(bRec); }
    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        return nested(0).discreteLobes(bRec, lobes);
    }

protected:
    explicit SurfaceWrapperBSDF(std::string plugin) : NestedBSDF(std::move(plugin), 1, 1) {}
    /// What the wrapper gives the shape it is attached to.
    virtual void decorate(Shape &shape) = 0;
};

} // namespace nori
