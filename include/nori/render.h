// The render loop: image blocks in parallel, each pixel's samples through the camera,
// integrator and reconstruction filter, merged into one image.
#pragma once

#include <nori/bitmap.h>

#include <atomic>

namespace nori {

class Scene;

struct RenderOptions {
    int threads = 0;            ///< worker threads; 0 = all cores
    size_t samplesPerPixel = 0; ///< 0 = the scene sampler's own count
    bool showProgress = true;   ///< progress bar on stderr
    /// When it becomes true, no new block or pixel is started and the blocks finished so
    /// far are returned (what SIGINT does).
    const std::atomic<bool> *cancel = nullptr;
};

struct RenderResult {
    Bitmap image;
    bool complete = true; ///< false when cancelled: only finished blocks are in image
    size_t blocksDone = 0;
    size_t blocksTotal = 0;
    size_t samplesPerPixel = 0;
    size_t samplesTaken = 0;   ///< camera samples of finished blocks
    size_t invalidSamples = 0; ///< NaN, infinite or negative radiance; not splatted
    double seconds = 0.0;
};

/// The number of threads used when RenderOptions::threads is 0.
int defaultThreadCount();

/// Renders the scene. Each pixel is seeded by its position, and blocks are merged in a
/// fixed order, so the image is bit-identical for any thread count.
RenderResult renderScene(Scene &scene, const RenderOptions &options = {});

} // namespace nori
