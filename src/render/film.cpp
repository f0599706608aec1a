#include <nori/film.h>

#include <algorithm>
#include <cmath>

namespace nori {

bool PixelStatistics::withinTolerance(float maxTolerance) const {
    if (decisionCount < 2 || count < 1)
        return false;
    const double m = decisionCount, mean = sum / m;
    const double variance = std::max(0.0, (sumOfSquares - m * mean * mean) / (m - 1.0));
    return 1.96 * std::sqrt(variance / double(count)) <= maxTolerance * mean;
}

Color3f halfBufferVariance(const Color4f &totalSum, const Color4f &evenSum) {
    const Color4f oddSum = totalSum - evenSum;
    if (evenSum.w() <= 0.0f || oddSum.w() <= 0.0f)
        return Color3f(0.0f);
    // The mean of two independent half estimates A and B has variance (Var A + Var B)/4,
    // and E[(A − B)²] = Var A + Var B: so (A − B)²/4 per pixel.
    const Color3f difference = evenSum.divideByFilterWeight() - oddSum.divideByFilterWeight();
    return difference * difference * 0.25f;
}

FilmBlock::FilmBlock(const Point2i &offset, const Vector2i &size,
                     const ReconstructionFilter *filter, const std::vector<AOV> &aovs,
                     bool pixelStatistics)
    : m_offset(offset), m_size(size),
      m_statistics(pixelStatistics ? static_cast<size_t>(size.prod()) : 0) {
    auto has = [&](AOV aov) { return std::find(aovs.begin(), aovs.end(), aov) != aovs.end(); };
    const bool layerWanted[kLayerCount] = {true,
                                           has(AOV::Variance),
                                           has(AOV::Albedo),
                                           has(AOV::Normal),
                                           has(AOV::Depth),
                                           has(AOV::Position),
                                           has(AOV::Emission)};
    for (int layer = 0; layer < kLayerCount; ++layer)
        if (layerWanted[layer]) {
            m_layers[layer] = std::make_unique<ImageBlock>(size, filter);
            m_layers[layer]->setOffset(offset);
        }
}

void FilmBlock::put(const FilmSample &sample) {
    auto splat = [&](int layer, const Color3f &value) {
        if (sample.ownPixel)
            m_layers[layer]->putInPixel(*sample.ownPixel, value, sample.filterSign);
        else
            m_layers[layer]->put(sample.position, value);
    };
    const bool even = m_layers[kEvenHalf] && sample.sampleIndex % 2 == 0;
    if (sample.splatted) {
        m_layers[kBeauty]->putInPixel(*sample.ownPixel, Color3f(0.0f), 1.0f);
        if (even)
            m_layers[kEvenHalf]->putInPixel(*sample.ownPixel, Color3f(0.0f), 1.0f);
    } else {
        splat(kBeauty, sample.radiance);
        if (even)
            splat(kEvenHalf, sample.radiance);
    }
    if (!sample.surface)
        return;
    const SurfaceAOVs &surface = *sample.surface;
    if (m_layers[kAlbedo])
        splat(kAlbedo, surface.albedo);
    if (m_layers[kNormal])
        splat(kNormal, Color3f(surface.normal.array()));
    if (m_layers[kDepth])
        splat(kDepth, Color3f(surface.depth));
    if (m_layers[kPosition])
        splat(kPosition, Color3f(surface.position.array()));
    if (m_layers[kEmission])
        splat(kEmission, surface.emission);
}

void FilmBlock::countSample(int x, int y) {
    if (!m_statistics.empty())
        ++m_statistics[index(x, y)].count;
}

void FilmBlock::countDecisionSample(int x, int y, float luminance) {
    if (m_statistics.empty())
        return;
    PixelStatistics &statistics = m_statistics[index(x, y)];
    ++statistics.decisionCount;
    statistics.sum += luminance;
    statistics.sumOfSquares += double(luminance) * luminance;
}

void FilmBlock::add(const FilmBlock &pass) {
    for (int layer = 0; layer < kLayerCount; ++layer)
        if (m_layers[layer])
            m_layers[layer]->put(*pass.m_layers[layer]);
    for (size_t i = 0; i < m_statistics.size(); ++i) {
        m_statistics[i].count += pass.m_statistics[i].count;
        m_statistics[i].decisionCount += pass.m_statistics[i].decisionCount;
        m_statistics[i].sum += pass.m_statistics[i].sum;
        m_statistics[i].sumOfSquares += pass.m_statistics[i].sumOfSquares;
    }
}

void FilmBlock::updateConvergence(size_t minSamples, float maxTolerance) {
    for (PixelStatistics &statistics : m_statistics)
        if (!statistics.converged && statistics.count >= minSamples)
            statistics.converged = statistics.withinTolerance(maxTolerance);
}

void FilmBlock::saveState(StateWriter &state) const {
    for (const auto &layer : m_layers)
        if (layer)
            state.writeArray(layer->data()->data(), static_cast<size_t>(layer->size()) * 4);
    state.write<uint64_t>(m_statistics.size());
    for (const PixelStatistics &statistics : m_statistics) {
        state.write(statistics.count);
        state.write(statistics.decisionCount);
        state.write(statistics.sum);
        state.write(statistics.sumOfSquares);
        state.write(statistics.converged);
    }
}

void FilmBlock::loadState(StateReader &state) {
    for (const auto &layer : m_layers)
        if (layer)
            state.readArray(layer->data()->data(), static_cast<size_t>(layer->size()) * 4);
    if (state.read<uint64_t>() != m_statistics.size())
        throw NoriException("{} does not fit this render: its pixel statistics differ",
                            state.what());
    for (PixelStatistics &statistics : m_statistics) {
        statistics.count = state.read<uint32_t>();
        statistics.decisionCount = state.read<uint32_t>();
        statistics.sum = state.read<double>();
        statistics.sumOfSquares = state.read<double>();
        statistics.converged = state.read<bool>();
    }
}

Film::Film(const Vector2i &size, const ReconstructionFilter *filter, std::vector<AOV> aovs,
           bool adaptive, bool splatting, int blockSize, std::vector<std::string> splatLayers)
    : m_size(size), m_filter(filter), m_aovs(std::move(aovs)),
      m_pixelStatistics(adaptive ||
                        std::find(m_aovs.begin(), m_aovs.end(), AOV::SampleCount) != m_aovs.end()),
      m_splatLayers(std::move(splatLayers)), m_merged(size, filter) {
    for (int y = 0; y < size.y(); y += blockSize)
        for (int x = 0; x < size.x(); x += blockSize)
            m_blocks.push_back(std::make_unique<FilmBlock>(
                Point2i(x, y),
                Vector2i(std::min(blockSize, size.x() - x), std::min(blockSize, size.y() - y)),
                filter, m_aovs, m_pixelStatistics));
    if (splatting)
        m_splats = std::make_unique<SplatBuffer>(
            size, filter, std::find(m_aovs.begin(), m_aovs.end(), AOV::Variance) != m_aovs.end(),
            static_cast<int>(m_splatLayers.size()));
}

void Film::addSplats(const std::vector<std::vector<SplatBuffer::Record>> &lists) {
    if (!m_splats)
        throw NoriException("Film::addSplats: the film was not made for an integrator that splats");
    m_splats->add(lists);
}

void Film::saveState(StateWriter &state) const {
    state.write<uint64_t>(m_blocks.size());
    for (const auto &block : m_blocks)
        block->saveState(state);
    state.write(m_splats != nullptr);
    if (m_splats)
        m_splats->saveState(state);
}

void Film::loadState(StateReader &state) {
    if (state.read<uint64_t>() != m_blocks.size())
        throw NoriException("{} does not fit this render: another image size", state.what());
    for (const auto &block : m_blocks)
        block->loadState(state);
    if (state.read<bool>() != (m_splats != nullptr))
        throw NoriException("{} does not fit this render: another integrator", state.what());
    if (m_splats)
        m_splats->loadState(state);
}

bool Film::needsSurfaceAOVs() const {
    return std::any_of(m_aovs.begin(), m_aovs.end(), [](AOV aov) {
        return aov == AOV::Albedo || aov == AOV::Normal || aov == AOV::Depth ||
               aov == AOV::Position || aov == AOV::Emission;
    });
}

std::unique_ptr<FilmBlock> Film::makePassBlock(size_t index) const {
    return std::make_unique<FilmBlock>(m_blocks[index]->offset(), m_blocks[index]->size(), m_filter,
                                       m_aovs, m_pixelStatistics);
}

size_t Film::convergedPixels() const {
    size_t total = 0;
    for (const auto &block : m_blocks)
        total += static_cast<size_t>(
            std::count_if(block->m_statistics.begin(), block->m_statistics.end(),
                          [](const PixelStatistics &statistics) { return statistics.converged; }));
    return total;
}

LayeredImage::Channel Film::filterWeights(const ImageBlock &block) const {
    const int border = block.getBorderSize();
    LayeredImage::Channel weights(m_size.y(), m_size.x());
    for (int y = 0; y < m_size.y(); ++y)
        for (int x = 0; x < m_size.x(); ++x)
            weights(y, x) = block(y + border, x + border).w();
    return weights;
}

const ImageBlock &Film::merge(int layer) const {
    m_merged.clear();
    for (const auto &block : m_blocks)
        m_merged.put(*block->m_layers[layer]);
    if (m_splats && (layer == FilmBlock::kBeauty || layer == FilmBlock::kEvenHalf)) {
        // The splats' sums carry no weight: the pixel's own samples' count divides them.
        const int border = m_merged.getBorderSize();
        for (int y = 0; y < m_size.y(); ++y)
            for (int x = 0; x < m_size.x(); ++x) {
                const Color3f &sum =
                    layer == FilmBlock::kBeauty ? m_splats->sum(x, y) : m_splats->evenSum(x, y);
                m_merged(y + border, x + border) += Color4f(sum.r(), sum.g(), sum.b(), 0.0f);
            }
    }
    return m_merged;
}

LayeredImage Film::develop(bool withWeights) const {
    LayeredImage result(m_size);
    const ImageBlock &beauty = merge(FilmBlock::kBeauty);
    result.addLayer("", {"R", "G", "B"}, beauty.toBitmap());
    if (m_splats) {
        // The integrator's extra layers (Integrator::splatLayers): their splat sums over
        // the weights of the pixels' own samples, as the image's (before `beauty` is reused).
        const LayeredImage::Channel weights = filterWeights(beauty);
        for (size_t k = 0; k < m_splatLayers.size(); ++k) {
            Bitmap values(m_size);
            for (int y = 0; y < m_size.y(); ++y)
                for (int x = 0; x < m_size.x(); ++x)
                    if (weights(y, x) != 0.0f)
                        values(y, x) =
                            m_splats->layerSum(static_cast<int>(k) + 1, x, y) / weights(y, x);
            result.addLayer(m_splatLayers[k], {"R", "G", "B"}, values);
        }
    }
    const bool variance = std::find(m_aovs.begin(), m_aovs.end(), AOV::Variance) != m_aovs.end();
    if (withWeights || variance)
        result.addChannel(kWeightChannel, filterWeights(beauty));
    if (variance) {
        const ImageBlock &even = merge(FilmBlock::kEvenHalf);
        result.addLayer(kEvenHalfLayer, {"R", "G", "B"}, even.toBitmap());
        result.addChannel(kEvenHalfWeightChannel, filterWeights(even));
    }
    for (AOV aov : m_aovs) {
        Bitmap values(m_size);
        switch (aov) {
        case AOV::Albedo:
            values = merge(FilmBlock::kAlbedo).toBitmap();
            break;
        case AOV::Normal:
            values = merge(FilmBlock::kNormal).toBitmap();
            break;
        case AOV::Depth:
            values = merge(FilmBlock::kDepth).toBitmap();
            break;
        case AOV::Position:
            values = merge(FilmBlock::kPosition).toBitmap();
            break;
        case AOV::Emission:
            values = merge(FilmBlock::kEmission).toBitmap();
            break;
        case AOV::SampleCount:
            for (const auto &block : m_blocks)
                for (int y = 0; y < block->size().y(); ++y)
                    for (int x = 0; x < block->size().x(); ++x)
                        values(block->offset().y() + y, block->offset().x() + x) = Color3f(
                            static_cast<float>(block->m_statistics[block->index(x, y)].count));
            break;
        case AOV::Variance: {
            const ImageBlock even = merge(FilmBlock::kEvenHalf);
            const ImageBlock &beauty = merge(FilmBlock::kBeauty);
            const int border = beauty.getBorderSize();
            for (int y = 0; y < m_size.y(); ++y)
                for (int x = 0; x < m_size.x(); ++x)
                    values(y, x) = halfBufferVariance(beauty(y + border, x + border),
                                                      even(y + border, x + border));
            break;
        }
        }
        result.addLayer(aovName(aov), aovChannels(aov), values);
    }
    return result;
}

} // namespace nori
