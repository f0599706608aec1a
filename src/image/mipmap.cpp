#include <nori/mipmap.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

/// An index wrapped into [0, size).
int wrapIndex(int i, int size, MIPMap::Wrap wrap) {
    switch (wrap) {
    case MIPMap::Wrap::Repeat:
        i %= size;
        return i < 0 ? i + size : i;
    case MIPMap::Wrap::Clamp:
        return std::clamp(i, 0, size - 1);
    case MIPMap::Wrap::Mirror: {
        // Period 2·size: 0 1 … size−1 size−1 … 1 0.
        const int period = 2 * size;
        i %= period;
        if (i < 0)
            i += period;
        return i < size ? i : period - 1 - i;
    }
    }
    return 0;
}

/// Weights of a 1D box downsampling from n to m samples: output j covers the input
/// interval [j·n/m, (j+1)·n/m), each input sample weighted by its overlap, normalised.
struct BoxWeights {
    int first;                  ///< first input sample
    std::vector<float> weights; ///< for inputs first, first + 1, ...
};

std::vector<BoxWeights> boxWeights(int n, int m) {
    std::vector<BoxWeights> result(m);
    const double ratio = double(n) / m;
    for (int j = 0; j < m; ++j) {
        const double begin = j * ratio, end = (j + 1) * ratio;
        const int first = static_cast<int>(std::floor(begin));
        const int last = std::min(n - 1, static_cast<int>(std::ceil(end)) - 1);
        result[j].first = first;
        for (int i = first; i <= last; ++i) {
            const double overlap = std::min(end, i + 1.0) - std::max(begin, double(i));
            result[j].weights.push_back(static_cast<float>(overlap / ratio));
        }
    }
    return result;
}

/// st moved by whole periods of the wrap mode (and clamped for Clamp) so that texel
/// indices stay small integers however far uv runs; NaN goes to 0.
Point2f reduce(const Point2f &st, MIPMap::Wrap wrap) {
    Point2f result;
    for (int i = 0; i < 2; ++i) {
        float x = std::isfinite(st[i]) ? st[i] : 0.0f;
        switch (wrap) {
        case MIPMap::Wrap::Repeat:
            x -= std::floor(x);
            break;
        case MIPMap::Wrap::Mirror:
            x -= 2.0f * std::floor(0.5f * x);
            break;
        case MIPMap::Wrap::Clamp:
            x = std::clamp(x, -1.0f, 2.0f);
            break;
        }
        result[i] = x;
    }
    return result;
}

/// A footprint axis with non-finite parts becomes a point.
Vector2f finiteOrZero(const Vector2f &v) {
    return v.allFinite() ? v : Vector2f(0.0f, 0.0f);
}

} // namespace

Bitmap MIPMap::downsample(const Bitmap &image) {
    const int width = std::max(1, image.width() / 2), height = std::max(1, image.height() / 2);
    // An even size halves exactly: each output is ½·a + ½·b, the same sums in the same
    // order as the weights below give (so the same bits), without their loop.
    const bool evenWidth = image.width() % 2 == 0, evenHeight = image.height() % 2 == 0;
    const std::vector<BoxWeights> wx =
        evenWidth ? std::vector<BoxWeights>() : boxWeights(image.width(), width);
    const std::vector<BoxWeights> wy =
        evenHeight ? std::vector<BoxWeights>() : boxWeights(image.height(), height);
    // Separable: rows first, then columns.
    Bitmap rows(Eigen::Vector2i(width, image.height()));
    for (int y = 0; y < image.height(); ++y) {
        const Color3f *in = &image.coeffRef(y, 0);
        Color3f *out = &rows.coeffRef(y, 0);
        if (evenWidth) {
            for (ptrdiff_t x = 0; x < width; ++x)
                out[x] = Color3f(0.0f) + 0.5f * in[2 * x] + 0.5f * in[2 * x + 1];
            continue;
        }
        for (int x = 0; x < width; ++x) {
            Color3f sum(0.0f);
            for (size_t k = 0; k < wx[x].weights.size(); ++k)
                sum += wx[x].weights[k] * in[wx[x].first + static_cast<int>(k)];
            out[x] = sum;
        }
    }
    Bitmap result(Eigen::Vector2i(width, height));
    for (Eigen::Index y = 0; y < height; ++y) {
        Color3f *out = &result.coeffRef(y, 0);
        if (evenHeight) {
            const Color3f *above = &rows.coeffRef(2 * y, 0), *below = &rows.coeffRef(2 * y + 1, 0);
            for (int x = 0; x < width; ++x)
                out[x] = Color3f(0.0f) + 0.5f * above[x] + 0.5f * below[x];
            continue;
        }
        for (int x = 0; x < width; ++x) {
            Color3f sum(0.0f);
            for (size_t k = 0; k < wy[y].weights.size(); ++k)
                sum += wy[y].weights[k] * rows.coeff(wy[y].first + static_cast<int>(k), x);
            out[x] = sum;
        }
    }
    return result;
}

MIPMap::MIPMap(Bitmap image) : m_base(std::move(image)) {
    if (m_base.width() < 1 || m_base.height() < 1)
        throw NoriException("MIPMap: empty image");
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < m_base.height(); ++y)
        for (int x = 0; x < m_base.width(); ++x)
            for (int c = 0; c < 3; ++c)
                sum[c] += m_base.coeff(y, x)[c];
    const double texels = double(m_base.width()) * m_base.height();
    m_average = Color3f(float(sum[0] / texels), float(sum[1] / texels), float(sum[2] / texels));
    // Each level halves the larger side (rounding down) until it is 1: ⌊log2 size⌋ times.
    const int size = std::max(m_base.width(), m_base.height());
    m_levelCount = 1 + (31 - __builtin_clz(static_cast<unsigned>(size)));
    if (m_levelCount == 1)
        m_pyramidBuilt.store(true, std::memory_order_release);
}

const Bitmap &MIPMap::level(int index) const {
    if (index == 0)
        return m_base;
    // Built aside and moved in whole: if a level's allocation throws, the next call
    // starts over from an empty pyramid.
    std::call_once(m_buildOnce, [this] {
        std::vector<Bitmap> pyramid;
        pyramid.reserve(m_levelCount - 1);
        for (int level = 1; level < m_levelCount; ++level)
            pyramid.push_back(downsample(level == 1 ? m_base : pyramid.back()));
        m_pyramid = std::move(pyramid);
        m_pyramidBuilt.store(true, std::memory_order_release);
    });
    return m_pyramid[index - 1];
}

Color3f MIPMap::texelOf(const Bitmap &image, int x, int y, Wrap wrap) {
    return image.coeff(wrapIndex(y, image.height(), wrap), wrapIndex(x, image.width(), wrap));
}

Color3f MIPMap::texel(int level, int x, int y, Wrap wrap) const {
    return texelOf(this->level(level), x, y, wrap);
}

Color3f MIPMap::nearest(const Point2f &stIn, Wrap wrap) const {
    const Point2f st = reduce(stIn, wrap);
    return texelOf(m_base, static_cast<int>(std::floor(st.x() * m_base.width())),
                   static_cast<int>(std::floor(st.y() * m_base.height())), wrap);
}

Color3f MIPMap::bilinear(int level, const Point2f &stIn, Wrap wrap) const {
    const Point2f st = reduce(stIn, wrap);
    const Bitmap &image = this->level(level);
    const float x = st.x() * image.width() - 0.5f, y = st.y() * image.height() - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - x0, fy = y - y0;
    return (1 - fx) * (1 - fy) * texelOf(image, x0, y0, wrap) +
           fx * (1 - fy) * texelOf(image, x0 + 1, y0, wrap) +
           (1 - fx) * fy * texelOf(image, x0, y0 + 1, wrap) +
           fx * fy * texelOf(image, x0 + 1, y0 + 1, wrap);
}

float MIPMap::trilinearLevel(const Vector2f &dst0In, const Vector2f &dst1In) const {
    const Vector2f dst0 = finiteOrZero(dst0In), dst1 = finiteOrZero(dst1In);
    const float resolution = static_cast<float>(std::max(m_base.width(), m_base.height()));
    const float width = 2.0f * std::max({std::abs(dst0.x()), std::abs(dst0.y()), std::abs(dst1.x()),
                                         std::abs(dst1.y())});
    const float level = std::log2(std::max(width * resolution, 1e-8f));
    return std::clamp(level, 0.0f, static_cast<float>(levels() - 1));
}

Color3f MIPMap::trilinear(const Point2f &st, const Vector2f &dst0, const Vector2f &dst1,
                          Wrap wrap) const {
    const float level = trilinearLevel(dst0, dst1);
    const int lower = static_cast<int>(std::floor(level));
    const float blend = level - lower;
    if (blend == 0.0f || lower + 1 >= levels())
        return bilinear(lower, st, wrap);
    return (1.0f - blend) * bilinear(lower, st, wrap) + blend * bilinear(lower + 1, st, wrap);
}

namespace {

/// Orders the axes so that dst0 is the major one and stretches the minor one so that
/// the eccentricity is at most maxAnisotropy (pbrt-v3 §10.4.2: blurrier, never aliased).
void clampEccentricity(Vector2f &dst0, Vector2f &dst1, float maxAnisotropy) {
    if (dst0.squaredNorm() < dst1.squaredNorm())
        std::swap(dst0, dst1);
    const float major = dst0.norm(), minor = dst1.norm();
    if (minor * maxAnisotropy < major && minor > 0.0f)
        dst1 *= major / (minor * maxAnisotropy);
    else if (minor == 0.0f && major > 0.0f)
        dst1 = Vector2f(-dst0.y(), dst0.x()) / maxAnisotropy;
}

} // namespace

float MIPMap::ewaLevel(Vector2f dst0, Vector2f dst1, float maxAnisotropy) const {
    dst0 = finiteOrZero(dst0);
    dst1 = finiteOrZero(dst1);
    clampEccentricity(dst0, dst1, maxAnisotropy);
    const float resolution = static_cast<float>(std::max(m_base.width(), m_base.height()));
    const float level = std::log2(std::max(dst1.norm() * resolution, 1e-8f));
    return std::clamp(level, 0.0f, static_cast<float>(levels() - 1));
}

Color3f MIPMap::ewa(const Point2f &stIn, Vector2f dst0, Vector2f dst1, float maxAnisotropy,
                    Wrap wrap) const {
    const Point2f st = reduce(stIn, wrap);
    dst0 = finiteOrZero(dst0);
    dst1 = finiteOrZero(dst1);
    clampEccentricity(dst0, dst1, maxAnisotropy);
    const float level = ewaLevel(dst0, dst1, maxAnisotropy);
    const int lower = static_cast<int>(std::floor(level));
    // A footprint wider than the image: the 1×1 level is the whole image's average
    // (filtering there would only loop over copies of that one texel).
    if (lower >= levels() - 1)
        return texel(levels() - 1, 0, 0, wrap);
    const float blend = level - lower;
    Color3f low = ewaOnLevel(lower, st, dst0, dst1, wrap);
    if (blend == 0.0f || lower + 1 >= levels())
        return low;
    return (1.0f - blend) * low + blend * ewaOnLevel(lower + 1, st, dst0, dst1, wrap);
}

Color3f MIPMap::ewaOnLevel(int level, const Point2f &st, const Vector2f &dst0, const Vector2f &dst1,
                           Wrap wrap) const {
    const Bitmap &image = this->level(level);
    const float w = static_cast<float>(image.width()), h = static_cast<float>(image.height());
    // In this level's texel units, texel centres at integers.
    const float s = st.x() * w - 0.5f, t = st.y() * h - 0.5f;
    const Vector2f a(dst0.x() * w, dst0.y() * h), b(dst1.x() * w, dst1.y() * h);
    // The implicit ellipse A s² + B s t + C t² = 1 with axes a and b, grown by one texel so
    // that it always covers some texels (Heckbert 1989, §3.5.5; pbrt-v3 §10.4.2).
    float A = a.y() * a.y() + b.y() * b.y() + 1.0f;
    float B = -2.0f * (a.x() * a.y() + b.x() * b.y());
    float C = a.x() * a.x() + b.x() * b.x() + 1.0f;
    const float invF = 1.0f / (A * C - B * B * 0.25f);
    A *= invF;
    B *= invF;
    C *= invF;
    // The ellipse's bounding box.
    const float det = -B * B + 4.0f * A * C, invDet = 1.0f / det;
    const float uSqrt = std::sqrt(det * C), vSqrt = std::sqrt(A * det);
    const int s0 = static_cast<int>(std::ceil(s - 2.0f * invDet * uSqrt));
    const int s1 = static_cast<int>(std::floor(s + 2.0f * invDet * uSqrt));
    const int t0 = static_cast<int>(std::ceil(t - 2.0f * invDet * vSqrt));
    const int t1 = static_cast<int>(std::floor(t + 2.0f * invDet * vSqrt));
    Color3f sum(0.0f);
    float weightSum = 0.0f;
    const float floor = std::exp(-2.0f);
    for (int it = t0; it <= t1; ++it) {
        const float tt = it - t;
        for (int is = s0; is <= s1; ++is) {
            const float ss = is - s;
            const float r2 = A * ss * ss + B * ss * tt + C * tt * tt;
            if (r2 < 1.0f) {
                const float weight = std::exp(-2.0f * r2) - floor;
                sum += weight * texelOf(image, is, it, wrap);
                weightSum += weight;
            }
        }
    }
    return weightSum > 0.0f ? Color3f(sum / weightSum) : bilinear(level, st, wrap);
}

} // namespace nori
