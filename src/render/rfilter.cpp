#include <nori/rfilter.h>

#include <algorithm>
#include <cmath>

namespace nori {

float ReconstructionFilter::checkedRadius(float radius, const char *filterName) {
    if (!(radius > 0.0f && radius <= kMaxRadius))
        throw NoriException("{} filter: 'radius' must lie in (0, {}] pixels, got {}", filterName,
                            kMaxRadius, radius);
    return radius;
}

FilterSampler::FilterSampler(const ReconstructionFilter *filter) {
    constexpr int kSteps = 32; // ImageBlock's kFilterResolution
    if (filter)
        m_radius = filter->getRadius();
    m_cdf.push_back(0.0f);
    for (int i = 0; i < kSteps; ++i) {
        m_values.push_back(filter ? filter->eval(m_radius * i / kSteps) : 1.0f);
        m_cdf.push_back(m_cdf.back() + std::abs(m_values.back()));
    }
    for (float &value : m_cdf)
        value /= m_cdf.back();
}

float FilterSampler::sample1D(float u, float &sign) const {
    // The filter is even: pick a side with the first half of u, then a step by the CDF,
    // then a point uniformly inside the step.
    const float side = u < 0.5f ? -1.0f : 1.0f;
    u = u < 0.5f ? 2.0f * u : 2.0f * u - 1.0f;
    const size_t step = static_cast<size_t>(std::clamp<std::ptrdiff_t>(
        std::upper_bound(m_cdf.begin(), m_cdf.end(), u) - m_cdf.begin() - 1, 0,
        static_cast<std::ptrdiff_t>(m_values.size()) - 1));
    const float width = m_cdf[step + 1] - m_cdf[step];
    const float within = width > 0.0f ? std::clamp((u - m_cdf[step]) / width, 0.0f, 1.0f) : 0.5f;
    sign = m_values[step] < 0.0f ? -1.0f : 1.0f;
    const float stepSize = m_radius / static_cast<float>(m_values.size());
    return side *
           std::min((static_cast<float>(step) + within) * stepSize, std::nextafter(m_radius, 0.0f));
}

Point2f FilterSampler::sample(const Point2f &u, float &sign) const {
    float signX, signY;
    const Point2f offset(sample1D(u.x(), signX), sample1D(u.y(), signY));
    sign = signX * signY;
    return offset;
}

} // namespace nori
