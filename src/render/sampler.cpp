#include <nori/sampler.h>
#include <nori/warp.h>

namespace nori {

// Weak, like the other warps (warp.h); here because it needs the Sampler.
__attribute__((weak)) Vector3f Warp::sampleUniformHemisphere(Sampler *sampler,
                                                             const Normal3f &northPole) {
    // A point uniform in the cube [-1, 1]³, kept when it falls in the unit ball: its
    // direction is then uniform on the sphere; flipped into northPole's hemisphere.
    while (true) {
        const Point2f xy = sampler->next2D();
        const Vector3f v(2.0f * xy.x() - 1.0f, 2.0f * xy.y() - 1.0f,
                         2.0f * sampler->next1D() - 1.0f);
        const float squaredNorm = v.squaredNorm();
        if (squaredNorm > 1e-8f && squaredNorm <= 1.0f) {
            const Vector3f direction = v / std::sqrt(squaredNorm);
            return direction.dot(northPole) < 0.0f ? Vector3f(-direction) : direction;
        }
    }
}

void Sampler::readCommonProperties(const PropertyList &props) {
    const int sampleCount = props.getInteger("sampleCount", 1);
    if (sampleCount <= 0)
        throw NoriException("{}: 'sampleCount' must be positive, got {}", pluginName(),
                            sampleCount);
    m_sampleCount = static_cast<size_t>(sampleCount);
    m_seed = static_cast<uint64_t>(props.getInteger("seed", 0));
    m_maxTolerance = props.getFloat("maxTolerance", 0.0f);
    if (!(m_maxTolerance >= 0.0f) || !std::isfinite(m_maxTolerance))
        throw NoriException("{}: 'maxTolerance' must be a non-negative number, got {}",
                            pluginName(), m_maxTolerance);
    // A standard deviation needs two samples; 16 keeps the first estimate of σ honest.
    const int minSamples = props.getInteger("minSamples", 16);
    if (minSamples < 2)
        throw NoriException("{}: 'minSamples' must be at least 2, got {}", pluginName(),
                            minSamples);
    m_minSamples = static_cast<size_t>(minSamples);
}

std::string Sampler::commonPropertiesString() const {
    std::string text = fmt::format("sampleCount={}, seed={}", m_sampleCount, m_seed);
    if (m_maxTolerance > 0.0f)
        text += fmt::format(", maxTolerance={}, minSamples={}", m_maxTolerance, m_minSamples);
    return text;
}

} // namespace nori
