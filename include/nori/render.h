// The render loop: passes over the whole image, each adding a few samples per pixel;
// within a pass, image blocks in parallel, each pixel's samples through the camera,
// integrator and reconstruction filter into the film.
#pragma once

#include <nori/aov.h>
#include <nori/bitmap.h>
#include <nori/layeredimage.h>

#include <atomic>
#include <functional>

namespace nori {

class Film;
class Scene;

/// What the render loop reports after every finished pass.
struct PassReport {
    size_t pass = 0;            ///< 1 for the first pass
    size_t samplesPerPixel = 0; ///< sample indices [0, samplesPerPixel) are done
    size_t targetSamplesPerPixel = 0;
    double seconds = 0.0; ///< since the render started
};

struct RenderOptions {
    int threads = 0;            ///< worker threads; 0 = all cores
    size_t samplesPerPixel = 0; ///< 0 = the scene sampler's own count
    /// The first sample index of every pixel: the render takes indices [firstSample,
    /// firstSample + samplesPerPixel), a slice of a larger render.
    uint32_t firstSample = 0;
    /// Also develop the filter weights (Film::develop's withWeights), so that renders of
    /// disjoint sample slices can be summed exactly.
    bool keepFilterWeights = false;
    /// Called (under a lock, from the worker threads) after every finished image block
    /// with the samples done so far and the total asked for: what a progress bar shows.
    std::function<void(size_t done, size_t total)> progress;
    /// When it becomes true, no new sample is started and the passes finished so far are
    /// returned (what SIGINT does): the pass under way is dropped.
    const std::atomic<bool> *cancel = nullptr;
    /// A time budget in seconds (0: none), counted from before the integrator's
    /// preprocessing: passes are rendered until it is spent, the last one shortened to
    /// fit, or until samplesPerPixel, whichever comes first.
    double timeBudget = 0.0;
    /// AOV layers to record besides the integrator's own `aovs`.
    std::vector<AOV> aovs;
    /// The pass schedule: 1, 1, 2, 4, ... samples per pixel, at least minPassSamples and
    /// at most maxPassSamples per pass (min = max = spp: the whole render in one pass).
    size_t minPassSamples = 1;
    size_t maxPassSamples = 64;
    /// Filter importance sampling (see FilterSampler) instead of splatting: each pixel
    /// from its own samples. Always on under adaptive sampling.
    bool filterImportanceSampling = false;
    /// Called (on the calling thread) after every finished pass with the film so far.
    std::function<void(const Film &film, const PassReport &report)> passFinished;
    /// Checkpoints: called (on the calling thread) after a pass, once checkpointSeconds
    /// have passed since the last checkpoint or the start (0: after every pass), with the
    /// render's state: the film's sums, the passes and sample indices done, the time
    /// spent, the integrator's state (Integrator::saveState). Not after the last pass.
    std::function<void(const std::string &state)> checkpoint;
    double checkpointSeconds = 0.0;
    /// A state `checkpoint` was given by an earlier run of this render (same scene and
    /// options): the render continues from it, and its image is the one the render
    /// without the interruption writes, bit for bit. `resumeName` names it in errors.
    const std::string *resumeState = nullptr;
    std::string resumeName = "checkpoint";
};

struct RenderResult {
    Bitmap image;         ///< the beauty
    LayeredImage layers;  ///< the beauty (R, G, B) and the AOV layers
    bool complete = true; ///< false when cancelled or out of time before samplesPerPixel
    bool cancelled = false;
    size_t passes = 0;
    size_t samplesPerPixel = 0;        ///< samples per pixel reached (adaptive: at most)
    size_t targetSamplesPerPixel = 0;  ///< what was asked for
    size_t samplesTaken = 0;           ///< camera samples in the image
    size_t convergedPixels = 0;        ///< pixels adaptive sampling stopped early
    size_t invalidSamples = 0;         ///< NaN, infinite or negative radiance; not splatted
    double seconds = 0.0;              ///< the whole render, preprocessing included (and a resumed
                                       ///< render's earlier runs)
    size_t resumedSamplesPerPixel = 0; ///< where a resumed render continued from
};

/// The number of threads used when RenderOptions::threads is 0.
int defaultThreadCount();

/// Renders the scene. Sample i of pixel p is a pure function of (seed, p, i), each block
/// sums its samples in a fixed order and blocks are merged in a fixed order, so the
/// image is bit-identical for any thread count.
RenderResult renderScene(Scene &scene, const RenderOptions &options = {});

} // namespace nori
