#include <nori/imageblock.h>

namespace nori {

ImageBlock::ImageBlock(const Vector2i &size, const ReconstructionFilter *filter)
    : m_size(size), m_filter(filter) {
    // Samples up to `radius` away from a pixel centre contribute to it.
    m_borderSize = static_cast<int>(std::ceil(m_filter.radius() - 0.5f));
    resize(size.y() + 2 * m_borderSize, size.x() + 2 * m_borderSize);
    clear();
}

void ImageBlock::put(const Point2f &position, const Color3f &value) {
    // Position relative to the block's storage, and shifted so that pixel centres are at
    // integer coordinates (pixel (i, j) covers [i, i+1) x [j, j+1)).
    Point2f pos(position.x() - 0.5f - static_cast<float>(m_offset.x() - m_borderSize),
                position.y() - 0.5f - static_cast<float>(m_offset.y() - m_borderSize));

    const float radius = m_filter.radius();
    const int xMin = std::max(0, static_cast<int>(std::ceil(pos.x() - radius)));
    const int yMin = std::max(0, static_cast<int>(std::ceil(pos.y() - radius)));
    const int xMax =
        std::min(static_cast<int>(cols()) - 1, static_cast<int>(std::floor(pos.x() + radius)));
    const int yMax =
        std::min(static_cast<int>(rows()) - 1, static_cast<int>(std::floor(pos.y() + radius)));

    for (int y = yMin; y <= yMax; ++y) {
        float weightY = m_filter.weight(static_cast<float>(y) - pos.y());
        for (int x = xMin; x <= xMax; ++x) {
            float weight = weightY * m_filter.weight(static_cast<float>(x) - pos.x());
            coeffRef(y, x) += Color4f(value, weight);
        }
    }
}

void ImageBlock::putInPixel(const Point2i &pixel, const Color3f &value, float weight) {
    coeffRef(pixel.y() - m_offset.y() + m_borderSize, pixel.x() - m_offset.x() + m_borderSize) +=
        Color4f(value, weight);
}

void ImageBlock::put(const ImageBlock &block) {
    // Both blocks' storage starts at offset - border; find the overlap and add.
    Vector2i shift = (block.getOffset() - Vector2i::Constant(block.getBorderSize())) -
                     (m_offset - Vector2i::Constant(m_borderSize));
    for (int y = 0; y < block.rows(); ++y) {
        int targetY = y + shift.y();
        if (targetY < 0 || targetY >= rows())
            continue;
        for (int x = 0; x < block.cols(); ++x) {
            int targetX = x + shift.x();
            if (targetX < 0 || targetX >= cols())
                continue;
            coeffRef(targetY, targetX) += block.coeff(y, x);
        }
    }
}

Bitmap ImageBlock::toBitmap() const {
    Bitmap result(m_size);
    for (int y = 0; y < m_size.y(); ++y)
        for (int x = 0; x < m_size.x(); ++x)
            result.coeffRef(y, x) =
                coeff(y + m_borderSize, x + m_borderSize).divideByFilterWeight();
    return result;
}

} // namespace nori
