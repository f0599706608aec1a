// Feature-guided denoising in the family of NFOR (Bitterli et al. 2016, "Nonlinearly
// Weighted First-order Regression for Denoising Monte Carlo Renderings"): each pixel's
// colour is the intercept of a weighted least-squares fit of the colours in its window
// to a linear function of the features; the weights are non-local means on the colour
// with the variance-normalised distance of Rousselle et al. 2012 ("Adaptive rendering
// with non-local means filtering", eq. 4). Each bandwidth gives two candidates, the
// first-order fit and the plain weighted mean (which cannot overshoot where the features
// do not explain the colour, as on a glossy highlight); each pixel blends the candidates
// by the squared share of the pixels around it that find each of least error as
// estimated by SURE (Rousselle et al. 2012, sec. 4; Li et al. 2012). The colour is
// divided by the albedo first and multiplied back after, so that texture detail comes
// from the noise-free albedo (demodulation, as in Zimmer et al. 2015 and SVGF).
#include "denoise/denoiser.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Cholesky>

#include <array>
#include <cmath>

namespace nori {

namespace {

using Plane = LayeredImage::Channel;

constexpr int kFeatures = 7;                 // albedo RGB, normal XYZ, depth
constexpr int kUnknowns = 1 + kFeatures + 2; // intercept, feature and screen slopes
using Design = Eigen::Matrix<float, kUnknowns, 1>;
using Gram = Eigen::Matrix<float, kUnknowns, kUnknowns>;
using Moments = Eigen::Matrix<float, kUnknowns, 3>;

constexpr int kTileSize = 32;
/// Neighbours whose weight is below this add nothing worth their cost.
constexpr float kMinWeight = 1e-4f;
/// Rousselle et al. 2012's ε in the distance's denominator: only noise-free pixels reach it.
constexpr float kDistanceEpsilon = 1e-10f;
/// The variance estimate of one pixel from two half-buffers has one degree of freedom
/// per channel; its mean over a (2·2 + 1)² box is steadier by a factor five.
constexpr int kVarianceRadius = 2;
/// That mean is taken of the relative variance σ²/(C̄² + ε), C̄ the colour's mean over a
/// 3×3 box, and scaled back: a plain box of σ² would spread a highlight's variance onto
/// the dark pixels beside it, whose variance-normalised distances to the highlight would
/// then be small enough to blend it in.
constexpr int kVarianceScaleRadius = 1;
constexpr float kVarianceScaleEpsilon = 0.01f;
/// SURE of a single pixel is too noisy to choose by; the votes of a 7×7 box are not.
constexpr int kVoteRadius = 3;
/// The colour is divided by (albedo + this): black albedo (background, emitters) keeps
/// a finite scale, and dark texels do not amplify noise beyond ten times.
constexpr float kDemodulationOffset = 0.1f;

/// What the filter reads, as planes of floats; invalid pixels (non-finite or negative
/// colour) are never anyone's neighbour.
struct Inputs {
    int width = 0, height = 0;
    std::array<Plane, 3> colour;     ///< demodulated: the beauty / modulation
    std::array<Plane, 3> variance;   ///< of the demodulated colour, smoothed
    std::array<Plane, 3> modulation; ///< albedo + kDemodulationOffset
    std::array<Plane, kFeatures> features;
    Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> valid;
};

/// The mean of `plane` over a (2r + 1)² box clamped to the image.
Plane boxFilter(const Plane &plane, int radius) {
    const Eigen::Index rows = plane.rows(), cols = plane.cols();
    Plane horizontal(rows, cols), result(rows, cols);
    for (Eigen::Index y = 0; y < rows; ++y)
        for (Eigen::Index x = 0; x < cols; ++x) {
            const Eigen::Index x0 = std::max<Eigen::Index>(0, x - radius);
            const Eigen::Index x1 = std::min<Eigen::Index>(cols - 1, x + radius);
            horizontal(y, x) = plane.row(y).segment(x0, x1 - x0 + 1).mean();
        }
    for (Eigen::Index y = 0; y < rows; ++y) {
        const Eigen::Index y0 = std::max<Eigen::Index>(0, y - radius);
        const Eigen::Index y1 = std::min<Eigen::Index>(rows - 1, y + radius);
        result.row(y) = horizontal.middleRows(y0, y1 - y0 + 1).colwise().mean();
    }
    return result;
}

/// Channel `k` of a layer as a plane; non-finite values become 0.
Plane channelPlane(const Bitmap &layer, int k) {
    Plane plane(layer.rows(), layer.cols());
    for (Eigen::Index y = 0; y < layer.rows(); ++y)
        for (Eigen::Index x = 0; x < layer.cols(); ++x) {
            const float value = layer(y, x)[k];
            plane(y, x) = std::isfinite(value) ? value : 0.0f;
        }
    return plane;
}

Inputs readInputs(const LayeredImage &image) {
    Inputs inputs;
    inputs.width = image.size().x();
    inputs.height = image.size().y();
    // layer() throws a NoriException naming a missing layer and the ones there are.
    const Bitmap beauty = image.layer("");
    std::array<Bitmap, 4> layers;
    for (size_t i = 0; i < denoiserAOVs().size(); ++i)
        layers[i] = image.layer(aovName(denoiserAOVs()[i]));
    const Bitmap &albedo = layers[0], &normal = layers[1], &depth = layers[2],
                 &variance = layers[3];

    inputs.valid.resize(inputs.height, inputs.width);
    for (int y = 0; y < inputs.height; ++y)
        for (int x = 0; x < inputs.width; ++x)
            inputs.valid(y, x) = beauty(y, x).isFinite().all() && (beauty(y, x) >= 0.0f).all();
    for (int k = 0; k < 3; ++k) {
        inputs.features[k] = channelPlane(albedo, k).max(0.0f);
        inputs.features[3 + k] = channelPlane(normal, k);
        inputs.modulation[k] = inputs.features[k] + kDemodulationOffset;
        inputs.colour[k] = channelPlane(beauty, k).max(0.0f) / inputs.modulation[k];
        // Var(C / m) = Var(C) / m², the albedo being (nearly) noise-free.
        const Plane demodulatedVariance =
            channelPlane(variance, k).max(0.0f) / inputs.modulation[k].square();
        const Plane scale =
            boxFilter(inputs.colour[k], kVarianceScaleRadius).square() + kVarianceScaleEpsilon;
        inputs.variance[k] = boxFilter(demodulatedVariance / scale, kVarianceRadius) * scale;
    }
    // Depth in units of the farthest depth seen, so that its slope's ridge is
    // scale-free like the other features'.
    const Plane depthPlane = channelPlane(depth, 0).max(0.0f);
    const float farthest = depthPlane.maxCoeff();
    inputs.features[6] = farthest > 0.0f ? Plane(depthPlane / farthest) : depthPlane;
    return inputs;
}

/// The candidate filters' output: per candidate, the filtered (demodulated) colour and
/// the SURE estimate of its squared error in the beauty's units.
struct Candidates {
    std::vector<std::array<Plane, 3>> filtered; ///< [candidate][channel]
    std::vector<Plane> sure;                    ///< [candidate]
};

class TileFilter {
public:
    /// Candidates 2b and 2b + 1 are the first-order fit and the weighted mean with
    /// bandwidth b.
    TileFilter(const Inputs &inputs, const DenoiserSettings &settings, Candidates &out)
        : m_in(inputs), m_settings(settings), m_out(out) {
        for (float k : settings.bandwidths)
            m_inverseBandwidthSquared.push_back(1.0f / (k * k));
    }

    void filter(int x0, int y0, int width, int height) const {
        const size_t bandwidths = m_inverseBandwidthSquared.size();
        const size_t pixels = static_cast<size_t>(width) * height;
        std::vector<Gram> grams(bandwidths * pixels, Gram::Zero());
        std::vector<Moments> moments(bandwidths * pixels, Moments::Zero());
        const int r = m_settings.searchRadius, f = m_settings.patchRadius;
        const float patchArea = static_cast<float>((2 * f + 1) * (2 * f + 1));
        Plane pixelDistance(height + 2 * f, width + 2 * f);
        Plane rowSums(height + 2 * f, width);

        for (int oy = -r; oy <= r; ++oy)
            for (int ox = -r; ox <= r; ++ox) {
                // Per-pixel distances over the tile grown by the patch radius, then their
                // patch means by separable box sums.
                for (int y = 0; y < height + 2 * f; ++y)
                    for (int x = 0; x < width + 2 * f; ++x)
                        pixelDistance(y, x) = distance(x0 + x - f, y0 + y - f, ox, oy);
                for (int y = 0; y < height + 2 * f; ++y)
                    for (int x = 0; x < width; ++x)
                        rowSums(y, x) = pixelDistance.row(y).segment(x, 2 * f + 1).sum();

                for (int y = 0; y < height; ++y) {
                    const int py = y0 + y, qy = py + oy;
                    if (qy < 0 || qy >= m_in.height)
                        continue;
                    for (int x = 0; x < width; ++x) {
                        const int px = x0 + x, qx = px + ox;
                        if (qx < 0 || qx >= m_in.width || !m_in.valid(qy, qx))
                            continue;
                        const float patchDistance =
                            std::max(0.0f, rowSums.col(x).segment(y, 2 * f + 1).sum() / patchArea);
                        const Design design = designRow(px, py, qx, qy, ox, oy);
                        const Eigen::Vector3f colour = colourAt(qx, qy);
                        const size_t pixel = static_cast<size_t>(y) * width + x;
                        for (size_t b = 0; b < bandwidths; ++b) {
                            const float weight =
                                std::exp(-patchDistance * m_inverseBandwidthSquared[b]);
                            if (weight < kMinWeight)
                                continue;
                            const Design weighted = weight * design;
                            grams[b * pixels + pixel].noalias() += weighted * design.transpose();
                            moments[b * pixels + pixel].noalias() += weighted * colour.transpose();
                        }
                    }
                }
            }

        for (size_t b = 0; b < bandwidths; ++b)
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    const size_t pixel = static_cast<size_t>(y) * width + x;
                    const Gram &gram = grams[b * pixels + pixel];
                    const Moments &moment = moments[b * pixels + pixel];
                    firstOrderFit(gram, moment, 2 * b, x0 + x, y0 + y);
                    weightedMean(gram, moment, 2 * b + 1, x0 + x, y0 + y);
                }
    }

private:
    Eigen::Vector3f colourAt(int x, int y) const {
        return {m_in.colour[0](y, x), m_in.colour[1](y, x), m_in.colour[2](y, x)};
    }

    /// Rousselle et al. 2012's distance between pixels p and q = p + o, averaged over
    /// the channels: the squared difference less the variance it is expected to have,
    /// in units of the pair's variance (bandwidth k = 1; clamped coordinates).
    float distance(int px, int py, int ox, int oy) const {
        px = std::clamp(px, 0, m_in.width - 1);
        py = std::clamp(py, 0, m_in.height - 1);
        const int qx = std::clamp(px + ox, 0, m_in.width - 1);
        const int qy = std::clamp(py + oy, 0, m_in.height - 1);
        float sum = 0.0f;
        for (int k = 0; k < 3; ++k) {
            const float vp = m_in.variance[k](py, px), vq = m_in.variance[k](qy, qx);
            const float difference = m_in.colour[k](py, px) - m_in.colour[k](qy, qx);
            sum +=
                (difference * difference - (vp + std::min(vp, vq))) / (kDistanceEpsilon + vp + vq);
        }
        return sum / 3.0f;
    }

    /// The regression's row for neighbour q of p: 1, the features relative to p's, and
    /// the offset in units of the search radius (so that p's own row is (1, 0, ...) and
    /// the fit's intercept is the estimate at p).
    Design designRow(int px, int py, int qx, int qy, int ox, int oy) const {
        Design design;
        design[0] = 1.0f;
        for (int k = 0; k < kFeatures; ++k)
            design[1 + k] = m_in.features[k](qy, qx) - m_in.features[k](py, px);
        const float scale = 1.0f / static_cast<float>(std::max(1, m_settings.searchRadius));
        design[1 + kFeatures] = static_cast<float>(ox) * scale;
        design[2 + kFeatures] = static_cast<float>(oy) * scale;
        return design;
    }

    /// Solves one pixel's normal equations (G + λ·Σw·I on the slopes) β = M and keeps
    /// the intercept; its derivative with respect to the pixel's own colour, for SURE,
    /// is w_pp·(G⁻¹)₀₀ with w_pp = 1.
    void firstOrderFit(const Gram &gram, const Moments &moment, size_t candidate, int x,
                       int y) const {
        using GramD = Eigen::Matrix<double, kUnknowns, kUnknowns>;
        GramD system = gram.cast<double>();
        const double totalWeight = system(0, 0);
        if (totalWeight > 0.0) {
            system.diagonal().tail<kUnknowns - 1>().array() += m_settings.ridge * totalWeight;
            const Eigen::LDLT<GramD> ldlt(system);
            const Eigen::Matrix<double, kUnknowns, 3> beta = ldlt.solve(moment.cast<double>());
            const double inverse00 = ldlt.solve(GramD::Identity().col(0).eval())(0);
            if (ldlt.info() == Eigen::Success && beta.allFinite() && std::isfinite(inverse00)) {
                store(candidate, x, y, beta.row(0).transpose().cast<float>(),
                      static_cast<float>(std::clamp(inverse00, 0.0, 1.0)));
                return;
            }
        }
        store(candidate, x, y, colourAt(x, y), 1.0f);
    }

    /// The weighted mean Σw·C / Σw, whose derivative in the pixel's own colour is 1/Σw.
    void weightedMean(const Gram &gram, const Moments &moment, size_t candidate, int x,
                      int y) const {
        const float totalWeight = gram(0, 0);
        if (totalWeight > 0.0f)
            store(candidate, x, y, moment.row(0).transpose() / totalWeight, 1.0f / totalWeight);
        else
            store(candidate, x, y, colourAt(x, y), 1.0f);
    }

    /// Stores a candidate's estimate and its SURE, Σ_ch m²·((F − C)² − σ² + 2σ²·∂F/∂C)
    /// (Stein 1981; Li et al. 2012, eq. 5), in the beauty's units through the modulation
    /// m. An invalid pixel is not in its own window: its derivative is 0.
    void store(size_t candidate, int x, int y, const Eigen::Vector3f &filtered,
               float selfDerivative) const {
        if (!m_in.valid(y, x))
            selfDerivative = 0.0f;
        const Eigen::Vector3f colour = colourAt(x, y);
        float sure = 0.0f;
        for (int k = 0; k < 3; ++k) {
            const float variance = m_in.variance[k](y, x);
            const float residual = filtered[k] - colour[k];
            const float modulation = m_in.modulation[k](y, x);
            sure += modulation * modulation *
                    (residual * residual - variance + 2.0f * variance * selfDerivative);
            m_out.filtered[candidate][k](y, x) = filtered[k];
        }
        m_out.sure[candidate](y, x) = sure;
    }

    const Inputs &m_in;
    const DenoiserSettings &m_settings;
    Candidates &m_out;
    std::vector<float> m_inverseBandwidthSquared;
};

} // namespace

const std::vector<AOV> &denoiserAOVs() {
    static const std::vector<AOV> aovs{AOV::Albedo, AOV::Normal, AOV::Depth, AOV::Variance};
    return aovs;
}

Bitmap denoise(const LayeredImage &image, const DenoiserSettings &settings) {
    if (settings.bandwidths.empty() || settings.searchRadius < 0 || settings.patchRadius < 0 ||
        !(settings.ridge >= 0.0f))
        throw NoriException("denoise: needs a bandwidth, non-negative radii and ridge");
    for (float k : settings.bandwidths)
        if (!(k > 0.0f) || !std::isfinite(k))
            throw NoriException("denoise: bandwidths must be positive, got {}", k);
    const Inputs inputs = readInputs(image);
    const int width = inputs.width, height = inputs.height;

    Candidates candidates;
    for (size_t c = 0; c < 2 * settings.bandwidths.size() + 1; ++c) {
        candidates.filtered.push_back(
            {Plane(height, width), Plane(height, width), Plane(height, width)});
        candidates.sure.emplace_back(height, width);
    }
    // The last candidate is the noisy image itself, whose error is its variance.
    {
        const size_t identity = candidates.sure.size() - 1;
        candidates.sure[identity].setZero();
        for (int k = 0; k < 3; ++k) {
            candidates.filtered[identity][k] = inputs.colour[k];
            candidates.sure[identity] += inputs.variance[k] * inputs.modulation[k].square();
        }
    }
    const TileFilter tileFilter(inputs, settings, candidates);
    const int tilesX = (width + kTileSize - 1) / kTileSize;
    const int tilesY = (height + kTileSize - 1) / kTileSize;
    tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
            const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
            tileFilter.filter(x0, y0, std::min(kTileSize, width - x0),
                              std::min(kTileSize, height - y0));
        });
    });

    // Each pixel votes for the candidate of least SURE at it, and counts the votes of
    // the candidates in a (2·3 + 1)² box: SURE of one pixel is too noisy to choose by,
    // and a vote, unlike the box's mean SURE, cannot be swamped by a few neighbours of
    // huge variance (an emitter's edge beside a black background).
    const size_t count = candidates.sure.size();
    std::vector<Plane> votes(count, Plane::Zero(height, width));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            size_t best = 0;
            for (size_t c = 1; c < count; ++c)
                if (candidates.sure[c](y, x) < candidates.sure[best](y, x))
                    best = c;
            votes[best](y, x) = 1.0f;
        }
    for (Plane &vote : votes)
        vote = boxFilter(vote, kVoteRadius);

    // The candidates are blended by the squares of their vote shares rather than the
    // winner taken: where two candidates poll alike, a hard choice flips between them
    // from pixel to pixel and leaves blotches; squaring still favours the majority.
    Bitmap result(image.size());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Eigen::Vector3f blended = Eigen::Vector3f::Zero();
            float totalWeight = 0.0f;
            for (size_t c = 0; c < count; ++c) {
                const float weight = votes[c](y, x) * votes[c](y, x);
                totalWeight += weight;
                for (int k = 0; k < 3; ++k)
                    blended[k] += weight * candidates.filtered[c][k](y, x);
            }
            // Every pixel casts a vote inside its own box, so totalWeight > 0.
            for (int k = 0; k < 3; ++k) {
                const float value = blended[k] / totalWeight * inputs.modulation[k](y, x);
                result(y, x)[k] = std::isfinite(value) ? std::max(0.0f, value) : 0.0f;
            }
        }
    return result;
}

} // namespace nori
