// A feature-guided denoiser for rendered images: per pixel, a first-order regression of
// the colour on the AOV features (albedo, normal, depth) and the screen position, over
// a window weighted by non-local means whose bandwidth follows the half-buffer variance.
// It needs the layers of denoiserAOVs() beside the beauty (nori --denoise records them).
#pragma once

#include <nori/aov.h>
#include <nori/layeredimage.h>

#include <vector>

namespace nori {

struct DenoiserSettings {
    int searchRadius = 8; ///< the regression window of a pixel is (2r + 1)² pixels
    int patchRadius = 3;  ///< non-local means compares (2f + 1)² patches
    /// The candidate filters' non-local-means bandwidths k (larger: smoother); each
    /// pixel takes the candidate of least estimated error (SURE).
    std::vector<float> bandwidths{0.5f, 1.0f};
    /// More candidates, whose non-local means compare the smaller (2g + 1)² patches of
    /// this radius g, at these bandwidths: near a corner or along a line one pixel wide
    /// (a light's edge), no (2f + 1)² patch matches the pixel's, which then stays alone,
    /// noisy, in every candidate above. None: no such candidates.
    int finePatchRadius = 1;
    std::vector<float> fineBandwidths{1.0f};
    /// Ridge regularisation of the feature slopes, as a feature variance: slopes along
    /// features that vary less than √ridge in a window are damped.
    float ridge = 1e-3f;
    int threads = 0; ///< 0: all cores
};

/// The layers denoise() needs besides the beauty.
const std::vector<AOV> &denoiserAOVs();

/// The denoised beauty of `image`, which must have the layers of denoiserAOVs() (a
/// NoriException names a missing one). Non-finite inputs are treated as unknown; the
/// result is finite and non-negative.
Bitmap denoise(const LayeredImage &image, const DenoiserSettings &settings = {});

/// The candidates denoise() blends, before it chooses: for each bandwidth b of the
/// settings, then each of the fine ones, the first-order fit (index 2b) and the weighted
/// mean (2b + 1); then the noisy image. A fine candidate is computed only where it
/// competes (DenoiserSettings::finePatchRadius), the coarse one standing in elsewhere. For
/// measuring the choice against an oracle that knows the reference.
std::vector<Bitmap> denoiserCandidates(const LayeredImage &image,
                                       const DenoiserSettings &settings = {});

} // namespace nori
