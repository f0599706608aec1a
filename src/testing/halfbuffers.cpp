#include "testing/halfbuffers.h"

#include <nori/film.h>
#include <nori/strutil.h>

#include <cmath>

namespace nori {

namespace {

constexpr const char *kColorChannels[3] = {"R", "G", "B"};

} // namespace

bool hasHalfBuffers(const LayeredImage &render) {
    const auto &channels = render.channels();
    for (const char *channel : kColorChannels)
        if (!channels.count(channel) ||
            !channels.count(std::string(kEvenHalfLayer) + "." + channel))
            return false;
    return channels.count(kWeightChannel) && channels.count(kEvenHalfWeightChannel);
}

HalfBufferErrors::HalfBufferErrors(const LayeredImage &render, int radius)
    : m_value(render.size()), m_difference(render.size()), m_radius(radius) {
    if (radius < 0)
        throw NoriException("the correlation radius must be at least 0 pixels, got {}", radius);
    if (!hasHalfBuffers(render))
        throw NoriException("has no half-buffers (the '{}' layer and the '{}' and '{}' "
                            "channels): render it with the variance layer (--aovs variance)",
                            kEvenHalfLayer, kWeightChannel, kEvenHalfWeightChannel);
    m_value = render.layer("");
    const Bitmap even = render.layer(kEvenHalfLayer);
    const LayeredImage::Channel &weight = render.channels().at(kWeightChannel),
                                &evenWeight = render.channels().at(kEvenHalfWeightChannel);
    for (int y = 0; y < m_value.rows(); ++y)
        for (int x = 0; x < m_value.cols(); ++x) {
            // The odd half from the sums: (w·L)_odd = (w·L)_all − (w·L)_even.
            const double all = weight(y, x), evenW = evenWeight(y, x), oddW = all - evenW;
            if (!(evenW > 0.0) || !(oddW > 0.0))
                throw NoriException("pixel ({}, {}) has no sample in one of its half-buffers: "
                                    "render at least 2 samples per pixel",
                                    x, y);
            for (int c = 0; c < 3; ++c) {
                const double odd =
                    (double(m_value(y, x)[c]) * all - double(even(y, x)[c]) * evenW) / oddW;
                m_difference(y, x)[c] = static_cast<float>(double(even(y, x)[c]) - odd);
            }
        }

    // ρ(δ) = Σ_p z_p·z_(p+δ) / Σ_p z_p², over the pixel pairs inside the image and the
    // three channels, of the differences standardised by their local scale,
    // z_p = d_p / (the root mean square of d over the pixels within the radius of p):
    // each pixel then weighs alike, so that the few pixels of the largest variance (a
    // light's edge, whose noise is aliasing rather than a smooth field) do not set the
    // correlation of all the others. ρ(−δ) = ρ(δ).
    const int side = 2 * m_radius + 1;
    const int width = int(m_value.cols()), height = int(m_value.rows());
    // Summed-area table of d² per channel, for the local means.
    Eigen::Array<Eigen::Array3d, Eigen::Dynamic, Eigen::Dynamic> table(height + 1, width + 1);
    table.setConstant(Eigen::Array3d::Zero());
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            table(y + 1, x + 1) = table(y, x + 1) + table(y + 1, x) - table(y, x) +
                                  m_difference(y, x).cast<double>().square();
    Eigen::Array<Eigen::Array3d, Eigen::Dynamic, Eigen::Dynamic> standardised(height, width);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int x0 = std::max(0, x - m_radius), x1 = std::min(width, x + m_radius + 1);
            const int y0 = std::max(0, y - m_radius), y1 = std::min(height, y + m_radius + 1);
            const Eigen::Array3d localMean =
                (table(y1, x1) - table(y0, x1) - table(y1, x0) + table(y0, x0)) /
                double((x1 - x0) * (y1 - y0));
            const Eigen::Array3d d = m_difference(y, x).cast<double>();
            standardised(y, x) = (localMean > 0.0).select(d / localMean.sqrt(), 0.0);
        }
    double squares = 0.0;
    for (const Eigen::Array3d &z : standardised.reshaped())
        squares += z.square().sum();
    m_correlation.assign(size_t(side) * side, 0.0);
    for (int dy = 0; dy <= m_radius; ++dy)
        for (int dx = -m_radius; dx <= m_radius; ++dx) {
            if (dy == 0 && dx <= 0)
                continue;
            double products = 0.0;
            for (int y = 0; y + dy < height; ++y)
                for (int x = std::max(0, -dx); x < width && x + dx < width; ++x)
                    products += (standardised(y, x) * standardised(y + dy, x + dx)).sum();
            const double rho = squares > 0.0 ? products / squares : 0.0;
            m_correlation[correlationIndex(dx, dy)] = rho;
            m_correlation[correlationIndex(-dx, -dy)] = rho;
        }
    m_correlation[correlationIndex(0, 0)] = 1.0;
}

double HalfBufferErrors::correlationFactor() const {
    double sum = 0.0;
    for (double rho : m_correlation)
        sum += rho;
    return sum;
}

std::array<RegionEstimate, 3> HalfBufferErrors::estimate(const ImageRegion &region) const {
    const int width = region.width > 0 ? region.width : int(m_value.cols());
    const int height = region.width > 0 ? region.height : int(m_value.rows());
    const double pixels = double(width) * height;
    std::array<RegionEstimate, 3> result;
    std::array<double, 3> sums{}, variances{}, uncorrelated{};
    for (int y = region.y; y < region.y + height; ++y)
        for (int x = region.x; x < region.x + width; ++x) {
            // Σ ρ(δ) over the offsets that stay inside the region.
            double correlated = 0.0;
            for (int dy = -m_radius; dy <= m_radius; ++dy)
                for (int dx = -m_radius; dx <= m_radius; ++dx)
                    if (y + dy >= region.y && y + dy < region.y + height && x + dx >= region.x &&
                        x + dx < region.x + width)
                        correlated += m_correlation[correlationIndex(dx, dy)];
            for (int c = 0; c < 3; ++c) {
                sums[size_t(c)] += m_value(y, x)[c];
                const double pixelVariance =
                    0.25 * double(m_difference(y, x)[c]) * double(m_difference(y, x)[c]);
                variances[size_t(c)] += pixelVariance * correlated;
                uncorrelated[size_t(c)] += pixelVariance;
            }
        }
    for (size_t c = 0; c < 3; ++c) {
        result[c].mean = sums[c] / pixels;
        // Noise in the pooled ρ could make the sum small or negative on a region of a few
        // pixels; it is never taken below a quarter of the uncorrelated sum.
        result[c].standardError =
            std::sqrt(std::max(variances[c], 0.25 * uncorrelated[c])) / pixels;
    }
    return result;
}

ImageRegion parseImageRegion(const std::string &name, const std::string &text,
                             const Eigen::Vector2i &size) {
    const std::vector<std::string> fields = tokenize(text, ",");
    if (fields.size() != 4)
        throw NoriException("region '{}': expected X,Y,W,H, got '{}'", name, text);
    ImageRegion region{name, toInt(fields[0], "region X"), toInt(fields[1], "region Y"),
                       toInt(fields[2], "region W"), toInt(fields[3], "region H")};
    if (region.x < 0 || region.y < 0 || region.width <= 0 || region.height <= 0 ||
        region.x > size.x() - region.width || region.y > size.y() - region.height)
        throw NoriException("region '{}' ({}) does not fit in the {}x{} image", name, text,
                            size.x(), size.y());
    return region;
}

} // namespace nori
