#include <nori/parallel.h>
#include <nori/splatbuffer.h>

namespace nori {

namespace {

/// Rows summed by one task of SplatBuffer::add.
constexpr int kRowsPerBand = 16;

/// 1/∫ f(c − x) dx over x in [0, extent], c = i + 1/2, for each pixel i of an axis.
std::vector<float> inverseCoverage(const FilterTable &filter, int extent) {
    std::vector<float> result(static_cast<size_t>(extent));
    for (int i = 0; i < extent; ++i) {
        const float centre = static_cast<float>(i) + 0.5f;
        const float coverage = filter.integral(centre - static_cast<float>(extent), centre);
        result[static_cast<size_t>(i)] = coverage != 0.0f ? 1.0f / coverage : 0.0f;
    }
    return result;
}

} // namespace

SplatBuffer::SplatBuffer(const Vector2i &size, const ReconstructionFilter *filter, bool evenHalf,
                         int extraLayers)
    : m_size(size), m_filter(filter), m_inverseCoverageX(inverseCoverage(m_filter, size.x())),
      m_inverseCoverageY(inverseCoverage(m_filter, size.y())), m_sum(size),
      m_layerSums(static_cast<size_t>(std::max(extraLayers, 0)), Bitmap(size)) {
    if (evenHalf)
        m_evenSum = Bitmap(size);
}

void SplatBuffer::put(const Record &record, int rowBegin, int rowEnd) {
    // Pixel centres at integer coordinates, as ImageBlock::put has them.
    const float px = record.position.x() - 0.5f, py = record.position.y() - 0.5f;
    const float radius = m_filter.radius();
    const int yMin = std::max(rowBegin, static_cast<int>(std::ceil(py - radius)));
    const int yMax = std::min(rowEnd - 1, static_cast<int>(std::floor(py + radius)));
    if (yMin > yMax)
        return;
    const int xMin = std::max(0, static_cast<int>(std::ceil(px - radius)));
    const int xMax = std::min(m_size.x() - 1, static_cast<int>(std::floor(px + radius)));
    Bitmap &sum = record.layer == 0 ? m_sum : m_layerSums.at(static_cast<size_t>(record.layer - 1));
    const bool even = record.layer == 0 && record.evenSample && hasEvenHalf();
    for (int y = yMin; y <= yMax; ++y) {
        const float weightY = m_filter.weight(static_cast<float>(y) - py) *
                              m_inverseCoverageY[static_cast<size_t>(y)];
        for (int x = xMin; x <= xMax; ++x) {
            const float weight = weightY * m_filter.weight(static_cast<float>(x) - px) *
                                 m_inverseCoverageX[static_cast<size_t>(x)];
            const Color3f value = record.value * weight;
            sum(y, x) += value;
            if (even)
                m_evenSum(y, x) += value;
        }
    }
}

void SplatBuffer::add(const std::vector<std::vector<Record>> &lists) {
    const int bands = (m_size.y() + kRowsPerBand - 1) / kRowsPerBand;
    parallelFor(0, bands, [&](int band) {
        const int rowBegin = band * kRowsPerBand;
        const int rowEnd = std::min(m_size.y(), rowBegin + kRowsPerBand);
        for (const std::vector<Record> &list : lists)
            for (const Record &record : list)
                put(record, rowBegin, rowEnd);
    });
}

namespace {

// A buffer left empty (m_evenSum without half-buffers) has no first pixel to take the
// address of: null then, with a count of 0 (UBSan saw the member call on null).
void saveBitmap(StateWriter &state, const Bitmap &bitmap) {
    const float *values = bitmap.size() > 0 ? bitmap.data()->data() : nullptr;
    state.writeArray(values, static_cast<size_t>(bitmap.size()) * 3);
}

void loadBitmap(StateReader &state, Bitmap &bitmap) {
    float *values = bitmap.size() > 0 ? bitmap.data()->data() : nullptr;
    state.readArray(values, static_cast<size_t>(bitmap.size()) * 3);
}

} // namespace

void SplatBuffer::saveState(StateWriter &state) const {
    saveBitmap(state, m_sum);
    saveBitmap(state, m_evenSum);
    state.write<uint64_t>(m_layerSums.size());
    for (const Bitmap &sum : m_layerSums)
        saveBitmap(state, sum);
}

void SplatBuffer::loadState(StateReader &state) {
    loadBitmap(state, m_sum);
    loadBitmap(state, m_evenSum);
    if (state.read<uint64_t>() != m_layerSums.size())
        throw NoriException("{} does not fit this render: another number of splat layers",
                            state.what());
    for (Bitmap &sum : m_layerSums)
        loadBitmap(state, sum);
}

} // namespace nori
