#include <nori/dpdf.h>

namespace nori {

void DiscretePDF::clear() {
    m_cdf.clear();
    m_cdf.push_back(0.0f);
    m_normalized = false;
    m_sum = m_normalization = 0.0f;
}

void DiscretePDF::append(float weight) {
    if (!(weight >= 0.0f) || !std::isfinite(weight))
        throw NoriException("DiscretePDF: weight {} of entry {} is negative or not finite", weight,
                            size());
    m_cdf.push_back(m_cdf.back() + weight);
    m_normalized = false;
}

float DiscretePDF::normalize() {
    m_sum = m_cdf.back();
    if (!(m_sum > 0.0f) || !std::isfinite(m_sum))
        throw NoriException("DiscretePDF: cannot normalise {} entries that sum to {}", size(),
                            m_sum);
    m_normalization = 1.0f / m_sum;
    // Divided, not multiplied by the reciprocal: w·(1/w) can round to 1 − 2⁻²⁴, which gave
    // the zero-weight entries after the last positive one that sliver of probability (an
    // environment map drew 6·10⁻⁸ of its samples in black texels). w/w is exactly 1.
    for (size_t i = 1; i < m_cdf.size(); ++i)
        m_cdf[i] /= m_sum;
    m_cdf.back() = 1.0f;
    m_normalized = true;
    return m_sum;
}

size_t DiscretePDF::sample(float u) const {
    // The first entry whose CDF exceeds u: zero-probability entries have an empty
    // interval and are never returned.
    auto it = std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), u);
    const size_t index = static_cast<size_t>(it - m_cdf.begin()) - 1;
    return std::min(index, size() - 1);
}

size_t DiscretePDF::sample(float u, float &pdf) const {
    const size_t index = sample(u);
    pdf = operator[](index);
    return index;
}

size_t DiscretePDF::sampleReuse(float &u) const {
    float pdf;
    return sampleReuse(u, pdf);
}

size_t DiscretePDF::sampleReuse(float &u, float &pdf) const {
    const size_t index = sample(u, pdf);
    u = std::min((u - m_cdf[index]) / pdf, 1.0f - std::numeric_limits<float>::epsilon() / 2);
    return index;
}

Distribution1D::Distribution1D(const std::vector<float> &weights) {
    if (weights.empty())
        throw NoriException("Distribution1D: no weights");
    m_cells.reserve(weights.size());
    for (float weight : weights)
        m_cells.append(weight);
    m_integral = m_cells.normalize() / static_cast<float>(weights.size());
}

float Distribution1D::sampleContinuous(float u, float &pdf, size_t &cell) const {
    cell = m_cells.sampleReuse(u);
    // Uniform within the cell: the density is the cell's probability times the count.
    pdf = m_cells[cell] * static_cast<float>(size());
    return std::min((static_cast<float>(cell) + u) / static_cast<float>(size()),
                    1.0f - std::numeric_limits<float>::epsilon() / 2);
}

size_t Distribution1D::sampleDiscrete(float &u, float &pmf) const {
    return m_cells.sampleReuse(u, pmf);
}

float Distribution1D::pdf(float x) const {
    if (!(x >= 0.0f && x < 1.0f))
        return 0.0f;
    const size_t cell = std::min(static_cast<size_t>(x * static_cast<float>(size())), size() - 1);
    return m_cells[cell] * static_cast<float>(size());
}

Distribution2D::Distribution2D(const std::vector<float> &weights, size_t width, size_t height) {
    if (width == 0 || height == 0 || weights.size() != width * height)
        throw NoriException("Distribution2D: {} weights do not form a {}x{} grid", weights.size(),
                            width, height);
    std::vector<float> rowIntegrals(height);
    m_conditionals.reserve(height);
    for (size_t row = 0; row < height; ++row) {
        std::vector<float> rowWeights(weights.begin() + row * width,
                                      weights.begin() + (row + 1) * width);
        float sum = 0.0f;
        for (float w : rowWeights)
            sum += w;
        // An all-zero row is never chosen by the marginal; keep it samplable anyway.
        if (sum == 0.0f)
            std::fill(rowWeights.begin(), rowWeights.end(), 1.0f);
        m_conditionals.emplace_back(rowWeights);
        rowIntegrals[row] = sum / static_cast<float>(width);
    }
    m_marginal = Distribution1D(rowIntegrals);
}

Point2f Distribution2D::sampleContinuous(const Point2f &u, float &pdf) const {
    Vector2i cell;
    return sampleContinuous(u, pdf, cell);
}

Point2f Distribution2D::sampleContinuous(const Point2f &u, float &pdf, Vector2i &cell) const {
    float marginalPdf, conditionalPdf;
    size_t row, column;
    const float y = m_marginal.sampleContinuous(u.y(), marginalPdf, row);
    const float x = m_conditionals[row].sampleContinuous(u.x(), conditionalPdf, column);
    // p(x, y) = p(y) · p(x | y).
    pdf = marginalPdf * conditionalPdf;
    cell = Vector2i(static_cast<int>(column), static_cast<int>(row));
    return Point2f(x, y);
}

float Distribution2D::pdf(const Point2f &p) const {
    const float marginal = m_marginal.pdf(p.y());
    if (marginal == 0.0f)
        return 0.0f;
    const size_t row =
        std::min(static_cast<size_t>(p.y() * static_cast<float>(m_conditionals.size())),
                 m_conditionals.size() - 1);
    return marginal * m_conditionals[row].pdf(p.x());
}

} // namespace nori
