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
#include <nori/parallel.h>

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
constexpr int kRowSize = kUnknowns + 3; // a neighbour's design row and colour

constexpr int kTileSize = 32;
/// Neighbours whose weight is below this add nothing worth their cost.
constexpr float kMinWeight = 1e-4f;
/// Rousselle et al. 2012's ε in the distance's denominator: only noise-free pixels reach it.
constexpr float kDistanceEpsilon = 1e-10f;
/// The variance estimate of one pixel from two half-buffers has one degree of freedom
/// per channel; its mean over a (2·3 + 1)² box has a seventh of its standard deviation.
constexpr int kVarianceRadius = 3;
/// That mean is taken of the relative variance σ²/(C̄² + ε), C̄ the colour's mean over a
/// 3×3 box, and scaled back: a plain box of σ² would spread a highlight's variance onto
/// the dark pixels beside it, whose variance-normalised distances to the highlight would
/// then be small enough to blend it in.
constexpr int kVarianceScaleRadius = 1;
constexpr float kVarianceScaleEpsilon = 0.01f;
/// SURE of a single pixel is too noisy to choose by; the votes of a 5×5 box are not.
constexpr int kVoteRadius = 2;
/// A pixel whose demodulated colour is more than this many times that of the brightest
/// of its eight neighbours is an outlier: a firefly, a speck of a caustic, or a light one
/// pixel wide. It is no other pixel's neighbour and its variance is not spread onto
/// theirs, so that a firefly is not smeared into a blob; its own pixel still chooses among
/// the candidates (a small light keeps its noisy value, a firefly of huge variance is
/// filtered away).
constexpr float kOutlierFactor = 2.0f;
/// The colour is divided by (albedo + this): black albedo (background, emitters) keeps
/// a finite scale, and dark texels do not amplify noise beyond ten times.
constexpr float kDemodulationOffset = 0.1f;

/// What the filter reads, as planes of floats; invalid pixels (non-finite or negative
/// colour, outliers) are never anyone's neighbour.
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

/// The mean of `plane` over the pixels of `mask` in a (2r + 1)² box clamped to the image
/// (0 where the box has none).
Plane maskedBoxFilter(const Plane &plane, const Plane &mask, int radius) {
    const Plane count = boxFilter(mask, radius);
    return (count > 0.0f).select(boxFilter(plane * mask, radius) / count, 0.0f);
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

/// Marks the outliers among the valid pixels invalid (kOutlierFactor): by the sum of the
/// demodulated colour's channels, so that texture edges are not outliers.
void markOutliers(Inputs &inputs) {
    const Plane brightness = inputs.colour[0] + inputs.colour[1] + inputs.colour[2];
    const auto valid = inputs.valid; // the outliers are judged against the inputs' validity
    for (int y = 0; y < inputs.height; ++y)
        for (int x = 0; x < inputs.width; ++x) {
            if (!valid(y, x))
                continue;
            float brightestNeighbour = 0.0f;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int qx = x + dx, qy = y + dy;
                    if ((dx != 0 || dy != 0) && qx >= 0 && qx < inputs.width && qy >= 0 &&
                        qy < inputs.height && valid(qy, qx))
                        brightestNeighbour = std::max(brightestNeighbour, brightness(qy, qx));
                }
            if (brightness(y, x) > kOutlierFactor * brightestNeighbour)
                inputs.valid(y, x) = false;
        }
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
    }
    markOutliers(inputs);
    const Plane valid = inputs.valid.cast<float>();
    for (int k = 0; k < 3; ++k) {
        // Var(C / m) = Var(C) / m², the albedo being (nearly) noise-free.
        const Plane demodulatedVariance =
            channelPlane(variance, k).max(0.0f) / inputs.modulation[k].square();
        const Plane scale =
            maskedBoxFilter(inputs.colour[k], valid, kVarianceScaleRadius).square() +
            kVarianceScaleEpsilon;
        const Plane smoothed =
            maskedBoxFilter(demodulatedVariance / scale, valid, kVarianceRadius) * scale;
        // Invalid pixels keep their own estimate: theirs is not their neighbours'.
        inputs.variance[k] = inputs.valid.select(smoothed, demodulatedVariance);
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

/// `plane` grown by `border` pixels on every side, each new pixel a copy of the nearest
/// image pixel, so that windows shifted past the image's edge need no clamping.
Plane padded(const Plane &plane, int border) {
    const Eigen::Index rows = plane.rows(), cols = plane.cols();
    Plane result(rows + 2 * Eigen::Index{border}, cols + 2 * Eigen::Index{border});
    for (Eigen::Index y = 0; y < result.rows(); ++y)
        for (Eigen::Index x = 0; x < result.cols(); ++x)
            result(y, x) = plane(std::clamp<Eigen::Index>(y - border, 0, rows - 1),
                                 std::clamp<Eigen::Index>(x - border, 0, cols - 1));
    return result;
}

class TileFilter {
public:
    /// Candidates 2b and 2b + 1 are the first-order fit and the weighted mean with
    /// bandwidth b.
    TileFilter(const Inputs &inputs, const DenoiserSettings &settings, Candidates &out)
        : m_in(inputs), m_settings(settings), m_out(out),
          m_border(settings.searchRadius +
                   std::max(settings.patchRadius, settings.finePatchRadius)) {
        for (float k : settings.bandwidths)
            m_inverseBandwidthSquared.push_back(1.0f / (k * k));
        for (float k : settings.fineBandwidths)
            m_inverseBandwidthSquared.push_back(1.0f / (k * k));
        for (int k = 0; k < 3; ++k) {
            m_paddedColour[k] = padded(inputs.colour[k], m_border);
            m_paddedVariance[k] = padded(inputs.variance[k], m_border);
        }
    }

    void filter(int x0, int y0, int width, int height) const {
        const int r = m_settings.searchRadius, side = 2 * r + 1;
        const bool hasFine = !m_settings.fineBandwidths.empty();
        std::vector<int> radii{m_settings.patchRadius};
        if (hasFine)
            radii.push_back(m_settings.finePatchRadius);
        const std::vector<Distances> distances = patchDistances(x0, y0, width, height, radii);

        // Per pixel, the weighted normal equations of its window, one set per bandwidth,
        // as one product Xᵀ·W·X of the neighbours' rows X = (design, colour).
        const size_t coarse = m_settings.bandwidths.size(), fine = m_settings.fineBandwidths.size();
        Eigen::Matrix<float, Eigen::Dynamic, kRowSize> rows(side * side, kRowSize);
        Eigen::ArrayXf coarseDistances(side * side), fineDistances(side * side);
        Eigen::MatrixXf weighted(side * side, static_cast<Eigen::Index>(coarse + fine) * kRowSize);
        Eigen::MatrixXf products(kRowSize, static_cast<Eigen::Index>(coarse + fine) * kRowSize);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const int px = x0 + x, py = y0 + y;
                const Eigen::Index pixel = static_cast<Eigen::Index>(y) * width + x;
                Eigen::Index count = 0;
                for (int oy = -r; oy <= r; ++oy) {
                    const int qy = py + oy;
                    if (qy < 0 || qy >= m_in.height)
                        continue;
                    for (int ox = -r; ox <= r; ++ox) {
                        const int qx = px + ox;
                        if (qx < 0 || qx >= m_in.width || !m_in.valid(qy, qx))
                            continue;
                        const Eigen::Index offset = (oy + r) * side + ox + r;
                        coarseDistances[count] = distances[0](offset, pixel);
                        if (hasFine)
                            fineDistances[count] = distances[1](offset, pixel);
                        rows.row(count) << designRow(px, py, qx, qy, ox, oy).transpose(),
                            colourAt(qx, qy).transpose();
                        ++count;
                    }
                }
                const auto neighbours = rows.topRows(count);
                solveAll(neighbours, coarseDistances.head(count), 0, coarse, weighted, products, px,
                         py, true);
                if (fine == 0)
                    continue;
                // The fine candidates compete only where the coarse ones left the pixel
                // (nearly) alone: the weights of the last coarse bandwidth (the widest of
                // the defaults) sum to less than 2, its own 1 and less than one neighbour's
                // (an invalid pixel, not its own neighbour: less than two).
                const float coarseWeight =
                    products(0, static_cast<Eigen::Index>(coarse - 1) * kRowSize);
                if (coarseWeight < 2.0f) {
                    solveAll(neighbours, fineDistances.head(count), coarse, fine, weighted,
                             products, px, py, true);
                } else {
                    // Not chosen here, but blended where a neighbour's vote chose them: the
                    // last coarse bandwidth's estimates stand in.
                    for (size_t b = coarse; b < coarse + fine; ++b)
                        for (size_t kind = 0; kind < 2; ++kind) {
                            const size_t standIn = 2 * (coarse - 1) + kind;
                            store(2 * b + kind, px, py, filteredAt(standIn, px, py), 1.0f, false);
                        }
                }
            }
    }

private:
    using Distances = Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic>;

    /// The candidates of bandwidths [first, first + count) of m_inverseBandwidthSquared
    /// at pixel (px, py), from its neighbours' rows and patch distances: all the
    /// bandwidths' weighted normal equations in one product Xᵀ·[W₀X | W₁X | ...].
    template <class Rows, class NeighbourDistances>
    void solveAll(const Rows &neighbours, const NeighbourDistances &patchDistance, size_t first,
                  size_t count, Eigen::MatrixXf &weighted, Eigen::MatrixXf &products, int px,
                  int py, bool competes) const {
        const Eigen::Index rows = neighbours.rows();
        const auto columns = static_cast<Eigen::Index>(count) * kRowSize;
        for (size_t b = 0; b < count; ++b) {
            const Eigen::ArrayXf weights =
                (patchDistance * -m_inverseBandwidthSquared[first + b]).exp();
            // Neighbours below kMinWeight add nothing worth keeping.
            weighted.block(0, static_cast<Eigen::Index>(b) * kRowSize, rows, kRowSize) =
                neighbours.array().colwise() * (weights < kMinWeight).select(0.0f, weights);
        }
        products.leftCols(columns).noalias() =
            neighbours.transpose() * weighted.topLeftCorner(rows, columns);
        for (size_t b = 0; b < count; ++b) {
            const auto column = static_cast<Eigen::Index>(b) * kRowSize;
            const Gram gram = products.block<kUnknowns, kUnknowns>(0, column);
            const Moments moment = products.block<kUnknowns, 3>(0, column + kUnknowns);
            firstOrderFit(gram, moment, 2 * (first + b), px, py, competes);
            weightedMean(gram, moment, 2 * (first + b) + 1, px, py, competes);
        }
    }

    /// The patch distance of every pixel p of the tile to each neighbour q = p + o of
    /// its window, for each patch radius f of `radii`: the mean over the (2f + 1)²
    /// patches around p and q and over the channels of Rousselle et al. 2012's pixel
    /// distance (eq. 4, bandwidth k = 1), ((C_p − C_q)² − (σ²_p + min(σ²_p, σ²_q))) /
    /// (ε + σ²_p + σ²_q): the squared difference less the variance it is expected to
    /// have, in units of the pair's variance. Per radius, one row per offset o (row-major
    /// over the window), one column per pixel of the tile (row-major), so that a pixel's
    /// distances lie together.
    std::vector<Distances> patchDistances(int x0, int y0, int width, int height,
                                          const std::vector<int> &radii) const {
        const int r = m_settings.searchRadius, side = 2 * r + 1;
        const int grown = *std::max_element(radii.begin(), radii.end());
        const int grownWidth = width + 2 * grown, grownHeight = height + 2 * grown;
        std::vector<Distances> distances(radii.size(), Distances(side * side, width * height));
        Plane pixelDistance(grownHeight, grownWidth), rowSums(grownHeight, width);
        Plane patch(height, width);
        // The tile grown by the largest patch radius, in the padded planes' coordinates.
        const int top = y0 - grown + m_border, left = x0 - grown + m_border;
        for (int oy = -r; oy <= r; ++oy)
            for (int ox = -r; ox <= r; ++ox) {
                pixelDistance.setZero();
                for (int k = 0; k < 3; ++k) {
                    const auto cp = m_paddedColour[k].block(top, left, grownHeight, grownWidth);
                    const auto cq =
                        m_paddedColour[k].block(top + oy, left + ox, grownHeight, grownWidth);
                    const auto vp = m_paddedVariance[k].block(top, left, grownHeight, grownWidth);
                    const auto vq =
                        m_paddedVariance[k].block(top + oy, left + ox, grownHeight, grownWidth);
                    pixelDistance +=
                        ((cp - cq).square() - (vp + vp.min(vq))) / (kDistanceEpsilon + vp + vq);
                }
                for (size_t i = 0; i < radii.size(); ++i) {
                    // Patch sums by separable box sums: along rows, then along columns,
                    // from the margin the larger radius left.
                    const int f = radii[i], margin = grown - f;
                    rowSums = pixelDistance.middleCols(margin, width);
                    for (int j = 1; j <= 2 * f; ++j)
                        rowSums += pixelDistance.middleCols(margin + j, width);
                    patch = rowSums.middleRows(margin, height);
                    for (int j = 1; j <= 2 * f; ++j)
                        patch += rowSums.middleRows(margin + j, height);
                    const float normalisation =
                        1.0f / static_cast<float>(3 * (2 * f + 1) * (2 * f + 1));
                    distances[i].row((oy + r) * side + ox + r) =
                        (Eigen::Map<const Eigen::ArrayXf>(patch.data(), patch.size()) *
                         normalisation)
                            .max(0.0f)
                            .transpose();
                }
            }
        return distances;
    }

    /// Candidate `candidate`'s estimate at (x, y), as stored.
    Eigen::Vector3f filteredAt(size_t candidate, int x, int y) const {
        return {m_out.filtered[candidate][0](y, x), m_out.filtered[candidate][1](y, x),
                m_out.filtered[candidate][2](y, x)};
    }

    Eigen::Vector3f colourAt(int x, int y) const {
        return {m_in.colour[0](y, x), m_in.colour[1](y, x), m_in.colour[2](y, x)};
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
    void firstOrderFit(const Gram &gram, const Moments &moment, size_t candidate, int x, int y,
                       bool competes) const {
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
                      static_cast<float>(std::clamp(inverse00, 0.0, 1.0)), competes);
                return;
            }
        }
        store(candidate, x, y, colourAt(x, y), 1.0f, competes);
    }

    /// The weighted mean Σw·C / Σw, whose derivative in the pixel's own colour is 1/Σw.
    void weightedMean(const Gram &gram, const Moments &moment, size_t candidate, int x, int y,
                      bool competes) const {
        const float totalWeight = gram(0, 0);
        if (totalWeight > 0.0f)
            store(candidate, x, y, moment.row(0).transpose() / totalWeight, 1.0f / totalWeight,
                  competes);
        else
            store(candidate, x, y, colourAt(x, y), 1.0f, competes);
    }

    /// Stores a candidate's estimate and its SURE, Σ_ch m²·((F − C)² − σ² + 2σ²·∂F/∂C)
    /// (Stein 1981; Li et al. 2012, eq. 5), in the beauty's units through the modulation
    /// m. An invalid pixel is not in its own window: its derivative is 0. A candidate that
    /// does not compete at the pixel gets an infinite SURE.
    void store(size_t candidate, int x, int y, const Eigen::Vector3f &filtered,
               float selfDerivative, bool competes) const {
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
        // A candidate that does not compete here is never the least.
        m_out.sure[candidate](y, x) = competes ? sure : kInfinity;
    }

    const Inputs &m_in;
    const DenoiserSettings &m_settings;
    Candidates &m_out;
    std::vector<float> m_inverseBandwidthSquared;
    /// The colour and its variance, padded by the search and patch radii.
    int m_border;
    std::array<Plane, 3> m_paddedColour, m_paddedVariance;
};

} // namespace

const std::vector<AOV> &denoiserAOVs() {
    static const std::vector<AOV> aovs{AOV::Albedo, AOV::Normal, AOV::Depth, AOV::Variance};
    return aovs;
}

namespace {

void checkSettings(const DenoiserSettings &settings) {
    if (settings.bandwidths.empty() || settings.searchRadius < 0 || settings.patchRadius < 0 ||
        settings.finePatchRadius < 0 || !(settings.ridge >= 0.0f))
        throw NoriException("denoise: needs a bandwidth, non-negative radii and ridge");
    std::vector<float> all = settings.bandwidths;
    all.insert(all.end(), settings.fineBandwidths.begin(), settings.fineBandwidths.end());
    for (float k : all)
        if (!(k > 0.0f) || !std::isfinite(k))
            throw NoriException("denoise: bandwidths must be positive, got {}", k);
}

/// Every candidate filter's output and SURE; the last candidate is the noisy image.
Candidates filterCandidates(const Inputs &inputs, const DenoiserSettings &settings) {
    const int width = inputs.width, height = inputs.height;
    Candidates candidates;
    const size_t filters = settings.bandwidths.size() + settings.fineBandwidths.size();
    for (size_t c = 0; c < 2 * filters + 1; ++c) {
        candidates.filtered.push_back(
            {Plane(height, width), Plane(height, width), Plane(height, width)});
        candidates.sure.emplace_back(height, width);
    }
    // The noisy image's error is its variance.
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
    ThreadLimit(settings.threads).run([&] {
        parallelFor(0, tilesX * tilesY, [&](int tile) {
            const int x0 = (tile % tilesX) * kTileSize, y0 = (tile / tilesX) * kTileSize;
            tileFilter.filter(x0, y0, std::min(kTileSize, width - x0),
                              std::min(kTileSize, height - y0));
        });
    });
    return candidates;
}

/// A candidate's demodulated colour times the modulation, finite and non-negative.
Color3f remodulated(const Inputs &inputs, const Eigen::Vector3f &colour, int x, int y) {
    Color3f result;
    for (int k = 0; k < 3; ++k) {
        const float value = colour[k] * inputs.modulation[k](y, x);
        result[k] = std::isfinite(value) ? std::max(0.0f, value) : 0.0f;
    }
    return result;
}

} // namespace

std::vector<Bitmap> denoiserCandidates(const LayeredImage &image,
                                       const DenoiserSettings &settings) {
    checkSettings(settings);
    const Inputs inputs = readInputs(image);
    const Candidates candidates = filterCandidates(inputs, settings);
    std::vector<Bitmap> result;
    for (const auto &filtered : candidates.filtered) {
        Bitmap &bitmap = result.emplace_back(image.size());
        for (int y = 0; y < inputs.height; ++y)
            for (int x = 0; x < inputs.width; ++x)
                bitmap(y, x) = remodulated(
                    inputs, {filtered[0](y, x), filtered[1](y, x), filtered[2](y, x)}, x, y);
    }
    return result;
}

Bitmap denoise(const LayeredImage &image, const DenoiserSettings &settings) {
    checkSettings(settings);
    const Inputs inputs = readInputs(image);
    const int width = inputs.width, height = inputs.height;
    const Candidates candidates = filterCandidates(inputs, settings);

    // Each pixel votes for the candidate of least SURE at it, and counts the votes of
    // the candidates in a (2·2 + 1)² box: SURE of one pixel is too noisy to choose by,
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
            result(y, x) = remodulated(inputs, blended / totalWeight, x, y);
        }
    return result;
}

} // namespace nori
