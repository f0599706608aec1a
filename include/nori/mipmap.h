// An image pyramid for filtered texture lookups (Williams 1983; pbrt-v3 §10.4): level 0
// is the image, each next level the box average of the one below at half the size
// (rounded down, any size), down to 1×1. Lookups: nearest and bilinear on level 0,
// trilinear between the two levels around the footprint's width, and elliptically
// weighted averages with a Gaussian (Heckbert 1989; pbrt-v3 §10.4.2).
// The levels above 0 are built on first use, by the first lookup (from any thread) that
// needs one: a texture filtered bilinearly (pbrt-v4's and Mitsuba's default) never pays
// their third more memory, nor their time at load.
#pragma once
#include <nori/bitmap.h>
#include <nori/vector.h>

#include <atomic>
#include <mutex>
#include <vector>

namespace nori {

class MIPMap {
public:
    enum class Wrap { Repeat, Clamp, Mirror };
    enum class Filter { Nearest, Bilinear, Trilinear, EWA };

    /// The pyramid of `image` (at least 1×1); its levels above 0 are built on first use.
    explicit MIPMap(Bitmap image);

    int levels() const { return m_levelCount; }
    /// Level `index` in [0, levels()); asking for one above 0 builds them all if they are
    /// not yet built (safe from several threads at once: one builds, the others wait).
    const Bitmap &level(int index) const;
    /// Whether the levels above 0 have been built (a 1×1 image has none to build).
    bool pyramidBuilt() const { return m_pyramidBuilt.load(std::memory_order_acquire); }
    /// The texel (x, y) of a level, with the coordinates wrapped.
    Color3f texel(int level, int x, int y, Wrap wrap) const;

    /// Nearest texel of level 0 at st ∈ [0, 1]² (t = 0 is the first image row).
    Color3f nearest(const Point2f &st, Wrap wrap) const;
    /// Bilinear interpolation on one level (texel centres at (i + ½)/size).
    Color3f bilinear(int level, const Point2f &st, Wrap wrap) const;
    /// The continuous level of a footprint: log2 of 2·max|∂(s,t)/∂(x,y)| in level-0
    /// texels (pbrt-v3 §10.4.3), clamped to [0, levels − 1].
    float trilinearLevel(const Vector2f &dst0, const Vector2f &dst1) const;
    /// Bilinear lookups on the two levels around trilinearLevel, mixed linearly.
    Color3f trilinear(const Point2f &st, const Vector2f &dst0, const Vector2f &dst1,
                      Wrap wrap) const;
    /// The level EWA filters on: log2 of the minor axis (after clamping the eccentricity
    /// to maxAnisotropy), clamped to [0, levels − 1].
    float ewaLevel(Vector2f dst0, Vector2f dst1, float maxAnisotropy) const;
    /// EWA on the two levels around ewaLevel, mixed linearly. dst0 and dst1 are the
    /// footprint's axes in st units (∂st/∂x, ∂st/∂y).
    Color3f ewa(const Point2f &st, Vector2f dst0, Vector2f dst1, float maxAnisotropy,
                Wrap wrap) const;
    /// EWA on one level: texels inside the ellipse weighted by exp(−2r²) − exp(−2).
    Color3f ewaOnLevel(int level, const Point2f &st, const Vector2f &dst0, const Vector2f &dst1,
                       Wrap wrap) const;

    /// The mean of level 0 (equal to the 1×1 level up to rounding).
    Color3f average() const { return m_average; }

    /// One level down: each output texel is the area-weighted average of the input texels
    /// it covers, the output being ⌊size/2⌋ (at least 1) on each axis.
    static Bitmap downsample(const Bitmap &image);

private:
    /// The texel (x, y) of `image`, with the coordinates wrapped.
    static Color3f texelOf(const Bitmap &image, int x, int y, Wrap wrap);

    Bitmap m_base; ///< level 0
    int m_levelCount;
    Color3f m_average;
    /// Levels 1, 2, ...: written once, inside m_buildOnce, read only after it.
    mutable std::vector<Bitmap> m_pyramid;
    mutable std::once_flag m_buildOnce;
    mutable std::atomic<bool> m_pyramidBuilt{false};
};

} // namespace nori
