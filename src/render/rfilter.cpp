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

FilterTable::FilterTable(const ReconstructionFilter *filter) {
    if (filter) {
        m_radius = filter->getRadius();
        for (int i = 0; i < kResolution; ++i)
            m_values[static_cast<size_t>(i)] =
                filter->eval(m_radius * static_cast<float>(i) / static_cast<float>(kResolution));
        m_values[kResolution] = 0.0f;
    } else {
        m_values.fill(1.0f);
    }
    m_lookupFactor = static_cast<float>(kResolution) / m_radius;
}

float FilterTable::halfIntegral(float t) const {
    const float step = m_radius / static_cast<float>(kResolution);
    const float clamped = std::min(t, m_radius);
    const int whole = std::min(static_cast<int>(clamped / step), kResolution);
    float sum = 0.0f;
    for (int i = 0; i < whole; ++i)
        sum += m_values[static_cast<size_t>(i)] * step;
    if (whole < kResolution)
        sum += m_values[static_cast<size_t>(whole)] * (clamped - static_cast<float>(whole) * step);
    return sum;
}

float FilterTable::integral(float a, float b) const {
    if (!(a < b))
        return 0.0f;
    // The table is even: fold each side of zero onto [0, radius].
    if (a >= 0.0f)
        return halfIntegral(b) - halfIntegral(a);
    if (b <= 0.0f)
        return halfIntegral(-a) - halfIntegral(-b);
    return halfIntegral(-a) + halfIntegral(b);
}

FilterSampler::FilterSampler(const ReconstructionFilter *filter) {
    constexpr int kSteps = FilterTable::kResolution; // as the film reconstructs
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

float FilterSampler::halfCdf(float t) const {
    const float position =
        std::clamp(t / m_radius, 0.0f, 1.0f) * static_cast<float>(m_values.size());
    const size_t step = std::min(static_cast<size_t>(position), m_values.size() - 1);
    return m_cdf[step] + (position - static_cast<float>(step)) * (m_cdf[step + 1] - m_cdf[step]);
}

float FilterSampler::sample1D(float u, float &sign, float lower, float upper) const {
    if (lower <= -m_radius && upper >= m_radius)
        return sample1D(u, sign);
    // The CDF of |f| over the whole line, G(t) = (1 + sgn t · C(|t|))/2 with C the half
    // CDF, is restricted to [lower, upper] by mapping u into [G(lower), G(upper)] and
    // inverted (inversion method on the truncated density; PBR 4th ed. §A.3.1).
    auto fullCdf = [&](float t) {
        const float c = halfCdf(std::abs(t));
        return 0.5f * (1.0f + (t < 0.0f ? -c : c));
    };
    const float from = fullCdf(std::max(lower, -m_radius)), to = fullCdf(std::min(upper, m_radius));
    const float v = from + u * (to - from);
    // sample1D's own inversion, with the side from v: v < 1/2 is the negative half, at
    // C⁻¹(1 − 2v) from the centre.
    if (v < 0.5f) {
        float offset = sample1D(0.5f + 0.5f * (1.0f - 2.0f * v), sign);
        offset = -offset;
        return std::clamp(offset, lower, upper);
    }
    return std::clamp(sample1D(0.5f + 0.5f * std::min(2.0f * v - 1.0f, 1.0f), sign), lower, upper);
}

Point2f FilterSampler::sample(const Point2f &u, float &sign, const Vector2f &lower,
                              const Vector2f &upper) const {
    float signX, signY;
    Point2f offset(sample1D(u.x(), signX, lower.x(), upper.x()),
                   sample1D(u.y(), signY, lower.y(), upper.y()));
    sign = signX * signY;
    return offset;
}

Point2f FilterSampler::sample(const Point2f &u, float &sign) const {
    float signX, signY;
    Point2f offset(sample1D(u.x(), signX), sample1D(u.y(), signY));
    sign = signX * signY;
    return offset;
}

} // namespace nori
