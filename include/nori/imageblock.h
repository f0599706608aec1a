// A rectangle of the image being rendered, accumulating filtered samples as
// (sum of w·L, sum of w) per pixel, with a border for the filter's support.
#pragma once

#include <nori/bitmap.h>
#include <nori/rfilter.h>

namespace nori {

class ImageBlock : public Eigen::Array<Color4f, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> {
public:
    using Base = Eigen::Array<Color4f, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    /// A block of `size` pixels; `filter` sets the border width and splat weights
    /// (nullptr means a box filter of radius 0.5, no border).
    ImageBlock(const Vector2i &size, const ReconstructionFilter *filter);

    void setOffset(const Point2i &offset) { m_offset = offset; }
    const Point2i &getOffset() const { return m_offset; }
    const Vector2i &getSize() const { return m_size; }
    int getBorderSize() const { return m_borderSize; }

    void clear() { setConstant(Color4f()); }
    /// Splats a sample at image position `position` (pixels, absolute) with the filter.
    void put(const Point2f &position, const Color3f &value);
    /// Adds a value with `weight` to the pixel `pixel` (absolute) only: a sample of filter
    /// importance sampling (see FilterSampler), whose weight is the filter's sign.
    void putInPixel(const Point2i &pixel, const Color3f &value, float weight);
    /// Adds another block's accumulated values (borders included) at its offset.
    void put(const ImageBlock &block);
    /// The normalised image of the block's interior (without border).
    Bitmap toBitmap() const;

private:
    Point2i m_offset{0, 0};
    Vector2i m_size;
    int m_borderSize = 0;
    FilterTable m_filter;
};

} // namespace nori
