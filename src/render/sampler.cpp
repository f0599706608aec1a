#include <nori/sampler.h>

namespace nori {

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
