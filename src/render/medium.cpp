#include <nori/medium.h>
#include <nori/phase.h>
#include <nori/shape.h>

namespace nori {

bool Medium::attachTo(NoriObject &parent, const std::string &name) {
    auto *shape = dynamic_cast<Shape *>(&parent);
    if (!shape)
        return false;
    shape->setMedium(name, std::static_pointer_cast<Medium>(shared_from_this()));
    return true;
}

void Medium::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EPhaseFunction)
        setUniqueChild(m_phase, child, "a medium");
    else
        NoriObject::addChild(child, name);
}

void Medium::activate() {
    if (!m_phase)
        m_phase = createDefault<PhaseFunction>("isotropic");
}

void Medium::readCoefficients(const PropertyList &props, const std::string &plugin, Color3f &sigmaT,
                              Color3f &albedo) {
    // sigma_s, sigma_a, sigma_t: the spellings of pbrt's and of many course scenes.
    const std::string sigmaSName = props.spelling("sigmaS", {"sigma_s"});
    const std::string sigmaAName = props.spelling("sigmaA", {"sigma_a"});
    const std::string sigmaTName = props.spelling("sigmaT", {"sigma_t"});
    const bool scatteringForm = props.has(sigmaSName) || props.has(sigmaAName);
    if (scatteringForm && (props.has(sigmaTName) || props.has("albedo")))
        throw NoriException("{}: give either 'sigmaS' and 'sigmaA', or 'sigmaT' and 'albedo', "
                            "not a mix",
                            plugin);
    auto checked = [&](const char *name, const Color3f &value) {
        if (!value.allFinite() || (value < 0.0f).any())
            throw NoriException("{}: '{}' must be finite and non-negative, got {}", plugin, name,
                                value.toString());
        return value;
    };
    const float scale = props.getFloat("scale", 1.0f);
    if (!(scale >= 0.0f) || !std::isfinite(scale))
        throw NoriException("{}: 'scale' must be finite and non-negative, got {}", plugin, scale);
    if (scatteringForm) {
        const Color3f sigmaS = checked("sigmaS", props.getColor(sigmaSName, Color3f(0.0f)));
        const Color3f sigmaA = checked("sigmaA", props.getColor(sigmaAName, Color3f(0.0f)));
        sigmaT = (sigmaS + sigmaA) * scale;
        // A channel that does not interact has no meaningful albedo; 0 keeps weights finite.
        albedo = (sigmaT > 0.0f).select(sigmaS * scale / sigmaT, Color3f(0.0f));
    } else {
        // Mitsuba 3's defaults.
        sigmaT = checked("sigmaT", props.getColor(sigmaTName, Color3f(1.0f))) * scale;
        albedo = checked("albedo", props.getColor("albedo", Color3f(0.75f)));
        if ((albedo > 1.0f).any())
            throw NoriException("{}: 'albedo' must lie in [0, 1], got {}", plugin,
                                albedo.toString());
    }
}

Color3f Medium::transmittance(const Ray3f &ray, PCG32 &rng, TransmittanceEstimator estimator,
                              float stepSize) const {
    switch (estimator) {
    case TransmittanceEstimator::Delta:
        return deltaTracking(ray, rng);
    case TransmittanceEstimator::Ratio:
        return ratioTracking(ray, rng);
    case TransmittanceEstimator::RayMarch:
        return rayMarching(ray, rng, stepSize);
    }
    return Color3f(0.0f);
}

Color3f Medium::deltaTracking(const Ray3f &ray, PCG32 &rng) const {
    // A tentative collision is real with probability P = mean(σt)/σ̄, which ends the
    // estimate at 0. For coloured σt the survivors carry (1 − σt/σ̄)/(1 − P), so each
    // step's expected factor is the ratio tracking one, 1 − σt/σ̄ (PBR 4th ed. §14.2.2);
    // for grey media the weight stays 1.
    Color3f weight(1.0f);
    const bool survived = forEachTentativeCollision(ray, rng, [&](float t, float sigmaMajorant) {
        const Color3f nullRatio = Color3f(1.0f) - sigmaT(ray(t)) / sigmaMajorant;
        const float realProbability = 1.0f - nullRatio.mean();
        if (realProbability >= 1.0f || rng.nextFloat() < realProbability)
            return false;
        weight *= nullRatio / (1.0f - realProbability);
        return true;
    });
    return survived ? weight : Color3f(0.0f);
}

Color3f Medium::ratioTracking(const Ray3f &ray, PCG32 &rng) const {
    // Each tentative collision multiplies by the probability 1 − σt/σ̄ that it is a null
    // collision (Novák et al. 2014, eq. 12).
    Color3f weight(1.0f);
    const bool survived = forEachTentativeCollision(ray, rng, [&](float t, float sigmaMajorant) {
        weight *= Color3f(1.0f) - sigmaT(ray(t)) / sigmaMajorant;
        return !(weight <= 0.0f).all();
    });
    return survived ? weight : Color3f(0.0f);
}

Color3f Medium::rayMarching(const Ray3f &ray, PCG32 &rng, float stepSize) const {
    // The optical depth τ = ∫ σt dt by the midpoint rule with one random offset for the
    // whole ray (stratified, so τ is unbiased); exp(−τ) is then biased by Jensen's
    // inequality, by an amount that vanishes with the step (PBR 2nd ed. §16.2.1).
    const float offset = rng.nextFloat();
    Color3f opticalDepth(0.0f);
    MajorantIterator segments = majorants(ray, ray.mint, ray.maxt);
    MajorantSegment segment;
    while (segments.next(segment)) {
        if (segment.sigmaMajorant <= 0.0f)
            continue;
        const float length = segment.tMax - segment.tMin;
        const int steps = std::max(1, int(std::ceil(length / stepSize)));
        const float step = length / float(steps);
        for (int i = 0; i < steps; ++i)
            opticalDepth += sigmaT(ray(segment.tMin + (float(i) + offset) * step)) * step;
    }
    return (-opticalDepth).exp();
}

} // namespace nori
