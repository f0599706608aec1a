// The film a render accumulates into: per image block, filtered sums of the beauty, of
// the AOV layers and of the even samples' half-buffer (for the variance), and per pixel
// the luminance statistics that adaptive sampling and the sampleCount layer use. Blocks
// keep their sums from pass to pass; a pass is rendered into blocks of its own and
// committed only when complete, so an interrupted pass leaves no trace.
#pragma once

#include <nori/aov.h>
#include <nori/imageblock.h>
#include <nori/layeredimage.h>
#include <nori/splatbuffer.h>
#include <nori/statestream.h>

#include <algorithm>
#include <array>
#include <memory>

namespace nori {

/// One camera sample as the film receives it.
struct FilmSample {
    Point2f position;             ///< film position in pixels, from the top-left corner
    Color3f radiance;             ///< camera weight × Li
    uint32_t sampleIndex = 0;     ///< even indices also go to the half-buffer
    const SurfaceAOVs *surface{}; ///< the surface AOVs, when the film records any
    /// Filter importance sampling (adaptive sampling): the pixel the sample was drawn
    /// for, which alone receives it with weight filterSign (see FilterSampler); nullptr:
    /// the sample is splatted with the filter into every pixel it reaches.
    const Point2i *ownPixel{};
    float filterSign = 1.0f;
    /// A sample of an integrator that splats (Integrator::splats): its radiance went to
    /// the film's SplatBuffer, and its own pixel (ownPixel) counts it with weight 1, the
    /// weight the splat sums are divided by; its AOVs go to that pixel alone.
    bool splatted = false;
};

/// One pixel's sample count, and the luminance statistics (unfiltered) on which adaptive
/// sampling decides to stop it. They come from a stream of decision samples of their own,
/// never put on the film: a pixel stopped by the values it averages keeps those whose
/// early samples happened to agree, and is biased (low, where rare bright samples carry
/// the light: −28 % in tests/test_progressive.cpp). Stopping on independent
/// samples makes the image samples' count independent of their values, so their mean
/// stays unbiased (the two-stage idea of Stein, Ann. Math. Statist. 16(3), 1945: the
/// sample size is set from samples that are not averaged).
struct PixelStatistics {
    uint32_t count = 0;                   ///< image samples (the sampleCount layer)
    uint32_t decisionCount = 0;           ///< decision samples
    double sum = 0.0, sumOfSquares = 0.0; ///< of the decision samples' luminances
    bool converged = false;               ///< adaptive sampling stopped the pixel

    /// Whether the 95% confidence interval of the image's mean, 1.96·σ/√n with n the image
    /// samples, lies within maxTolerance·μ; μ and σ² (unbiased) from the decision samples.
    bool withinTolerance(float maxTolerance) const;
};

/// The decision samples a pixel takes beside `imageSamples` image samples in a pass under
/// adaptive sampling: a quarter as many, at least one.
inline uint32_t decisionSamplesFor(uint32_t imageSamples) {
    return std::max<uint32_t>(1, imageSamples / 4);
}

/// The variance of a pixel's mean from its two half estimates (even and odd sample
/// indices), given the filtered sums (w·L, w) of all its samples and of the even ones;
/// 0 when either half has no weight (one sample or none).
Color3f halfBufferVariance(const Color4f &totalSum, const Color4f &evenSum);

/// The channels of a render with the variance layer, and of every part of a split render
/// (see renderpart.h): the filter weight of every pixel, and the even samples'
/// half-buffer. With them, parts are merged exactly and a region's error is estimated.
constexpr const char *kWeightChannel = "weight.W";
constexpr const char *kEvenHalfLayer = "evenHalf";
constexpr const char *kEvenHalfWeightChannel = "evenHalf.W";

class FilmBlock {
public:
    /// `pixelStatistics`: whether to keep PixelStatistics (adaptive sampling, the
    /// sampleCount layer), 24 bytes a pixel that other renders do without.
    FilmBlock(const Point2i &offset, const Vector2i &size, const ReconstructionFilter *filter,
              const std::vector<AOV> &aovs, bool pixelStatistics);

    const Point2i &offset() const { return m_offset; }
    const Vector2i &size() const { return m_size; }
    /// The filtered beauty sums (a sampler's prepare() sees them).
    const ImageBlock &beauty() const { return *m_layers[kBeauty]; }

    /// Splats a sample into every layer the film records.
    void put(const FilmSample &sample);
    /// Counts a finished image sample of the pixel at `offset() + (x, y)` (when the block
    /// keeps statistics).
    void countSample(int x, int y);
    /// Adds a decision sample's luminance to the pixel's statistics (adaptive sampling).
    void countDecisionSample(int x, int y, float luminance);
    /// The decision samples the pixel at `offset() + (x, y)` has taken.
    uint32_t decisionSamples(int x, int y) const {
        return m_statistics.empty() ? 0 : m_statistics[index(x, y)].decisionCount;
    }
    /// Whether adaptive sampling has stopped the pixel at `offset() + (x, y)`.
    bool isConverged(int x, int y) const {
        return !m_statistics.empty() && m_statistics[index(x, y)].converged;
    }
    /// Adds a pass's block (same region and layers) to this one.
    void add(const FilmBlock &pass);
    /// Marks pixels with at least minSamples samples whose mean is within tolerance as
    /// converged (adaptive sampling).
    void updateConvergence(size_t minSamples, float maxTolerance);

    /// Every sum and statistic of the block, for a checkpoint, and back.
    void saveState(StateWriter &state) const;
    void loadState(StateReader &state);

private:
    friend class Film;
    size_t index(int x, int y) const { return static_cast<size_t>(y) * m_size.x() + x; }

    /// The filtered sums the film keeps: the beauty, the even samples' half of it, and
    /// the surface AOVs (depth as grey).
    enum Layer { kBeauty, kEvenHalf, kAlbedo, kNormal, kDepth, kPosition, kEmission, kLayerCount };

    Point2i m_offset;
    Vector2i m_size;
    std::array<std::unique_ptr<ImageBlock>, kLayerCount> m_layers;
    std::vector<PixelStatistics> m_statistics;
};

class Film {
public:
    /// The film of an image of `size` pixels, split into blocks of at most blockSize²
    /// pixels, row by row; `adaptive`: keep the statistics adaptive sampling needs. The
    /// image-sized buffer that develop() merges into is allocated here, so that a film
    /// too large for memory fails before rendering, not after.
    /// `splatting`: the integrator splats (Integrator::splats), and the film keeps a
    /// SplatBuffer for it.
    /// `splatLayers`: the names of an integrator's extra layers of splats
    /// (Integrator::splatLayers), written after the image.
    Film(const Vector2i &size, const ReconstructionFilter *filter, std::vector<AOV> aovs,
         bool adaptive, bool splatting = false, int blockSize = 32,
         std::vector<std::string> splatLayers = {});

    const Vector2i &size() const { return m_size; }
    const std::vector<AOV> &aovs() const { return m_aovs; }
    /// Whether samples must carry their surface AOVs.
    bool needsSurfaceAOVs() const;

    size_t blockCount() const { return m_blocks.size(); }
    FilmBlock &block(size_t index) { return *m_blocks[index]; }
    const FilmBlock &block(size_t index) const { return *m_blocks[index]; }
    /// An empty block over the same region as block `index`, for a pass to render into.
    std::unique_ptr<FilmBlock> makePassBlock(size_t index) const;

    /// Pixels adaptive sampling has stopped.
    size_t convergedPixels() const;

    /// Adds a pass's splats (the film was made with `splatting`), one list per block in
    /// block order: see SplatBuffer::add.
    void addSplats(const std::vector<std::vector<SplatBuffer::Record>> &lists);

    /// Every block's sums and statistics and the splat sums, for a checkpoint; loadState
    /// restores them into a film made for the same image (else a NoriException).
    void saveState(StateWriter &state) const;
    void loadState(StateReader &state);

    /// The image: the beauty as R, G, B and one layer per AOV. Blocks are merged in
    /// index order, so every pixel sums the same values in the same order every time.
    /// Not thread-safe (it reuses one merge buffer). With the variance layer, also the
    /// even samples' half-buffer (kEvenHalfLayer, kEvenHalfWeightChannel) and the filter
    /// weights (kWeightChannel): what estimates the error of a region's mean, pixels'
    /// correlations included (testing/halfbuffers.h). `withWeights`: the filter weights
    /// even without the variance layer (a part of a split render, to be merged).
    LayeredImage develop(bool withWeights = false) const;

private:
    /// One layer of every block, merged into m_merged, with the splat sums added to the
    /// beauty and to the even half.
    const ImageBlock &merge(int layer) const;
    /// The interior's filter weights (the w of each pixel's sums).
    LayeredImage::Channel filterWeights(const ImageBlock &block) const;

    Vector2i m_size;
    const ReconstructionFilter *m_filter;
    std::vector<AOV> m_aovs;
    bool m_pixelStatistics;
    std::vector<std::unique_ptr<FilmBlock>> m_blocks;
    std::vector<std::string> m_splatLayers;
    std::unique_ptr<SplatBuffer> m_splats; ///< only for an integrator that splats
    mutable ImageBlock m_merged;
};

} // namespace nori
