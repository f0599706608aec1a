#include <nori/albedotable.h>
#include <nori/lowdiscrepancy.h>
#include <nori/parallel.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

/// The node index below x in [0, 1] on a grid of `count` nodes, and the weight of the next.
void gridCell(float x, int count, int &lower, int &upper, float &t) {
    if (count == 1) {
        lower = upper = 0;
        t = 0.0f;
        return;
    }
    const float position = std::clamp(x, 0.0f, 1.0f) * static_cast<float>(count - 1);
    lower = std::min(static_cast<int>(position), count - 2);
    upper = lower + 1;
    t = position - static_cast<float>(lower);
}

} // namespace

AlbedoTable::AlbedoTable(int muCount, int paramCount, int samples, const SampleWeight &weight)
    : m_muCount(muCount), m_paramCount(paramCount),
      m_values(static_cast<size_t>(muCount) * paramCount),
      m_rowMaxima(static_cast<size_t>(paramCount)) {
    parallelFor(0, muCount * paramCount, [&](int index) {
        const int i = index % muCount, j = index / muCount;
        // Nodes at μ = x² for x evenly spaced: albedos change fastest at grazing angles.
        const float x =
            muCount > 1 ? static_cast<float>(i) / static_cast<float>(muCount - 1) : 1.0f;
        const float mu = std::max(1e-4f, x * x);
        const float p =
            paramCount > 1 ? static_cast<float>(j) / static_cast<float>(paramCount - 1) : 0.0f;
        const Vector3f wi(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
        double sum = 0.0;
        for (int s = 0; s < samples; ++s) {
            const Point2f u(fractionToFloat(sobolSample(static_cast<uint32_t>(s), 0)),
                            fractionToFloat(sobolSample(static_cast<uint32_t>(s), 1)));
            sum += weight(wi, p, u);
        }
        m_values[static_cast<size_t>(index)] = static_cast<float>(sum / samples);
    });
    for (int j = 0; j < paramCount; ++j) {
        const auto row = m_values.begin() + static_cast<ptrdiff_t>(j) * muCount;
        m_rowMaxima[static_cast<size_t>(j)] = *std::max_element(row, row + muCount);
    }
}

float AlbedoTable::operator()(float mu, float p) const {
    int i0, i1, j0, j1;
    float s, t;
    gridCell(std::sqrt(std::max(0.0f, mu)), m_muCount, i0, i1, s);
    gridCell(p, m_paramCount, j0, j1, t);
    const float below = (1.0f - s) * node(i0, j0) + s * node(i1, j0);
    const float above = (1.0f - s) * node(i0, j1) + s * node(i1, j1);
    return (1.0f - t) * below + t * above;
}

float AlbedoTable::maxOverMu(float p) const {
    int j0, j1;
    float t;
    gridCell(p, m_paramCount, j0, j1, t);
    return (1.0f - t) * m_rowMaxima[static_cast<size_t>(j0)] +
           t * m_rowMaxima[static_cast<size_t>(j1)];
}

} // namespace nori
