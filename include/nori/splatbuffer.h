// The light that samples put on the film at positions of their own choosing (light
// tracing; see Splat in integrator.h), summed over the whole image per pixel j as
// value·f(position − c_j)/F_j, F_j the filter's integral over the image around c_j. The
// film adds these sums to its pixels' filtered sums, whose weights count each pixel's own
// samples, so that a pixel is its samples' mean plus (1/spp)·Σ value·f/F.
#pragma once

#include <nori/bitmap.h>
#include <nori/rfilter.h>
#include <nori/statestream.h>

#include <vector>

namespace nori {

class SplatBuffer {
public:
    /// One splat as the render loop hands it over: where, how much, and whether its
    /// sample's index is even (the half-buffer of the variance layer).
    struct Record {
        Point2f position;
        Color3f value;
        bool evenSample = false;
        int layer = 0; ///< 0: the image; k ≥ 1: extra layer k (Splat::layer)
    };

    /// A buffer for an image of `size` pixels reconstructed with `filter` (nullptr: the
    /// box of radius 1/2); `evenHalf`: also sum the even samples' splats; `extraLayers`:
    /// sums for that many extra layers (no even half).
    SplatBuffer(const Vector2i &size, const ReconstructionFilter *filter, bool evenHalf,
                int extraLayers = 0);

    /// Adds a pass's splats, list after list and each list in order, so that every pixel
    /// sums the same values in the same order for any thread count. Bands of rows are
    /// summed in parallel.
    void add(const std::vector<std::vector<Record>> &lists);

    /// Σ value·f/F at pixel (x, y), and over the splats of even samples alone.
    const Color3f &sum(int x, int y) const { return m_sum(y, x); }
    const Color3f &evenSum(int x, int y) const { return m_evenSum(y, x); }
    bool hasEvenHalf() const { return m_evenSum.size() > 0; }
    /// Σ value·f/F at pixel (x, y) over the splats of extra layer k ≥ 1.
    const Color3f &layerSum(int k, int x, int y) const {
        return m_layerSums[static_cast<size_t>(k - 1)](y, x);
    }

    /// The sums, for a checkpoint, and back (into a buffer of the same size and layers).
    void saveState(StateWriter &state) const;
    void loadState(StateReader &state);

private:
    /// Adds `record` to the pixels of rows [rowBegin, rowEnd) that the filter reaches.
    void put(const Record &record, int rowBegin, int rowEnd);

    Vector2i m_size;
    FilterTable m_filter;
    /// 1/F_j = 1/(Fx(x)·Fy(y)): the filter is separable, and so is its integral.
    std::vector<float> m_inverseCoverageX, m_inverseCoverageY;
    Bitmap m_sum, m_evenSum;
    std::vector<Bitmap> m_layerSums;
};

} // namespace nori
