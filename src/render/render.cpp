#include <nori/film.h>
#include <nori/hash.h>
#include <nori/parallel.h>
#include <nori/render.h>
#include <nori/scene.h>

#include <chrono>
#include <cmath>
#include <mutex>

namespace nori {

namespace {

bool isCancelled(const RenderOptions &options) {
    return options.cancel && options.cancel->load(std::memory_order_relaxed);
}

/// Mixed into the sampler's seed for adaptive sampling's decision samples.
constexpr uint64_t kDecisionStream = 0xdec15105;

/// An integrator that splats renders passes of at most this many samples (over all
/// pixels): its splats are kept until the pass ends, a few records of 24 bytes a sample.
constexpr size_t kSplattingSamplesPerPass = size_t(1) << 19;

/// Sample indices [first, end) of every pixel.
struct SampleRange {
    uint32_t first, end;
};

/// Renders the samples `range` of the block's pixels that adaptive sampling has not
/// stopped into `pass`, and under adaptive sampling each such pixel's decision samples
/// (see PixelStatistics) from `decisionSampler`. An integrator that splats puts every
/// sample's light, its own and its splats, into `splats` instead. Returns false when
/// cancelled part-way.
bool renderBlockPass(const Scene &scene, Sampler &sampler, Sampler *decisionSampler,
                     const Film &film, const FilterSampler &filterSampler,
                     const FilmBlock &accumulated, FilmBlock &pass, SampleRange range,
                     const RenderOptions &options, std::vector<SplatBuffer::Record> &splats,
                     size_t &validSamples, size_t &invalidSamples) {
    const Integrator *integrator = scene.getIntegrator();
    const bool surfaceAOVs = film.needsSurfaceAOVs();
    const bool splatting = integrator->splats();
    // Under adaptive sampling each pixel is reconstructed from its own samples, drawn
    // from the filter: with splatting, a stopped pixel would keep taking its running
    // neighbours' samples, and its filter would lean toward them (by whole units at the
    // edge of a light). The samples of an integrator that splats go to the SplatBuffer,
    // which divides by the filter's integral instead of the sum of weights: uniform
    // positions there.
    // A camera that samples beyond the image's border (pbrt-v4's film) takes each pixel's
    // samples from its whole filter, past the edge.
    const bool sampleBorder = scene.getCamera()->samplesBorder();
    const bool importanceSampleFilter =
        !splatting &&
        (options.filterImportanceSampling || sampler.getMaxTolerance() > 0.0f || sampleBorder);
    std::vector<Splat> sampleSplats;
    sampler.prepare(pass.beauty());
    if (decisionSampler)
        decisionSampler->prepare(pass.beauty());
    const uint32_t decisionCount = decisionSamplesFor(range.end - range.first);
    const Vector2f imageSize = film.size().cast<float>();
    const Camera &camera = *scene.getCamera();

    // One sample of `pixel` from `generator`: its film position, the filter's sign there,
    // its value, and (when wanted) its surface AOVs.
    struct Sample {
        Point2f position;
        float filterSign = 1.0f;
        Color3f value;
        SurfaceAOVs surface;
    };
    auto trace = [&](Sampler &generator, const Point2i &pixel, uint32_t index, bool aovs) {
        // The fixed order of dimensions: film position, aperture, then the integrator's.
        generator.generate(pixel, index);
        Sample sample;
        // Filter importance sampling keeps positions inside the image, where splatting
        // takes its samples: an edge pixel sees the filter cut at the edge either way,
        // unless the camera samples its border.
        const Point2f centre = pixel.cast<float>() + Point2f(0.5f, 0.5f);
        if (!importanceSampleFilter)
            sample.position = Point2f(pixel.cast<float>() + generator.next2D());
        else if (sampleBorder)
            sample.position =
                Point2f(centre + filterSampler.sample(generator.next2D(), sample.filterSign));
        else
            sample.position =
                Point2f(centre + filterSampler.sample(generator.next2D(), sample.filterSign,
                                                      -centre, imageSize - centre));
        const Point2f apertureSample = generator.next2D();
        Ray3f ray;
        sample.value = scene.sampleCameraRay(ray, sample.position, apertureSample);
        // A weight of zero (a lens blocked the ray) leaves the ray unset: no light.
        const bool traced = !(sample.value == 0.0f).all();
        if (aovs && traced)
            sample.surface = traceSurfaceAOVs(
                scene, ray, hashValues(generator.getSeed(), pixel.x(), pixel.y(), index));
        if (traced) {
            const Color3f cameraWeight = sample.value;
            sample.value *= splatting
                                ? integrator->LiAndSplats(&scene, &generator, ray, sampleSplats)
                                : integrator->Li(&scene, &generator, ray);
            for (Splat &splat : sampleSplats)
                if (splat.atSample) {
                    splat.position = sample.position;
                    splat.value *= cameraWeight;
                }
            // The sensor's white balance, a linear map: per sample, so that the variance
            // and adaptive sampling see the image that is written.
            if (camera.balancesWhite()) {
                sample.value = camera.sensorResponse(sample.value);
                for (Splat &splat : sampleSplats)
                    splat.value = camera.sensorResponse(splat.value);
            }
        }
        return sample;
    };

    for (int y = 0; y < pass.size().y(); ++y) {
        for (int x = 0; x < pass.size().x(); ++x) {
            if (accumulated.isConverged(x, y))
                continue;
            const Point2i pixel = pass.offset() + Vector2i(x, y);
            for (uint32_t index = range.first; index < range.end; ++index) {
                // Checked every sample (a relaxed load costs nothing next to a path), so
                // Ctrl-C is prompt even when a pass has many samples per pixel.
                if (isCancelled(options))
                    return false;
                sampleSplats.clear();
                const Sample sample = trace(sampler, pixel, index, surfaceAOVs);
                const bool valid = sample.value.isValid();
                if (!valid)
                    ++invalidSamples;
                if (splatting) {
                    // The sample counts in its pixel's weight whatever its values: the
                    // weights divide the splats of every pixel's samples. An invalid
                    // value, its own or a splat's, is dropped alone.
                    const bool even = index % 2 == 0;
                    if (valid)
                        splats.push_back({sample.position, sample.value, even});
                    for (const Splat &splat : sampleSplats) {
                        if (splat.value.isValid())
                            splats.push_back({splat.position, splat.value, even, splat.layer});
                        else if (splat.layer == 0)
                            ++invalidSamples;
                    }
                } else if (!valid) {
                    continue;
                }
                pass.put({sample.position, sample.value, index,
                          surfaceAOVs ? &sample.surface : nullptr,
                          importanceSampleFilter || splatting ? &pixel : nullptr, sample.filterSign,
                          splatting});
                pass.countSample(x, y);
                if (valid)
                    ++validSamples;
            }
            if (!decisionSampler)
                continue;
            // The decision samples, numbered on from the pixel's earlier ones.
            const uint32_t first = accumulated.decisionSamples(x, y);
            for (uint32_t index = first; index < first + decisionCount; ++index) {
                if (isCancelled(options))
                    return false;
                const Sample sample = trace(*decisionSampler, pixel, index, false);
                if (sample.value.isValid())
                    pass.countDecisionSample(x, y, sample.value.getLuminance());
            }
        }
    }
    return true;
}

/// Samples per pixel of pass `pass` (0-based): 1, 1, 2, 4, ... within [minimum, maximum],
/// so that early passes show a whole frame quickly and sample counts stay powers of two
/// (where Sobol' points are best stratified) until the cap.
size_t scheduledPassSize(size_t pass, size_t minimum, size_t maximum) {
    const size_t doubling = pass <= 1 ? 1 : size_t(1) << std::min<size_t>(pass - 1, 40);
    return std::max<size_t>(1, std::min(std::max(doubling, minimum), maximum));
}

} // namespace

int defaultThreadCount() {
    return maxParallelism();
}

RenderResult renderScene(Scene &scene, const RenderOptions &options) {
    const Camera *camera = scene.getCamera();
    const Vector2i outputSize = camera->getOutputSize();

    std::unique_ptr<Sampler> prototype = scene.getSampler()->clone();
    if (options.samplesPerPixel > 0)
        prototype->setSampleCount(options.samplesPerPixel);
    const size_t targetSpp =
        std::min<size_t>(prototype->getSampleCount(), UINT32_MAX - options.firstSample);

    std::vector<AOV> aovs = scene.getIntegrator()->aovs();
    for (AOV aov : options.aovs)
        if (std::find(aovs.begin(), aovs.end(), aov) == aovs.end())
            aovs.push_back(aov);
    const bool splatting = scene.getIntegrator()->splats();
    if (splatting && prototype->getMaxTolerance() > 0.0f)
        throw NoriException("adaptive sampling (the sampler's maxTolerance) cannot be used with "
                            "the integrator '{}': its samples also light other pixels, which "
                            "would not stop with theirs",
                            scene.getIntegrator()->pluginName());
    Film film(outputSize, camera->getReconstructionFilter(), aovs,
              prototype->getMaxTolerance() > 0.0f, splatting, 32,
              splatting ? scene.getIntegrator()->splatLayers() : std::vector<std::string>());
    const FilterSampler filterSampler(camera->getReconstructionFilter());

    ThreadLimit threads(options.threads);
    // The time budget and the reported time count the integrator's preprocessing (a
    // photon map, a light BVH): it is part of what the render costs.
    const auto start = std::chrono::steady_clock::now();
    auto secondsSince = [](std::chrono::steady_clock::time_point from) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - from).count();
    };
    auto elapsedSeconds = [&] { return secondsSince(start); };
    // The integrator's own parallel work (a photon map) keeps to the threads asked for.
    threads.run([&] { scene.getIntegrator()->preprocess(&scene); });
    const auto passesStart = std::chrono::steady_clock::now();

    RenderResult result;
    result.targetSamplesPerPixel = targetSpp;
    const size_t pixelCount = static_cast<size_t>(outputSize.prod());
    size_t samplesDone = 0; // for the progress callback: stopped pixels count as done
    std::mutex mutex;

    size_t sppDone = 0;
    double earlierSeconds = 0.0; // a resumed render's earlier runs
    if (options.resumeState) {
        StateReader state(*options.resumeState, options.resumeName);
        sppDone = state.read<uint64_t>();
        result.passes = state.read<uint64_t>();
        result.samplesTaken = state.read<uint64_t>();
        result.invalidSamples = state.read<uint64_t>();
        samplesDone = state.read<uint64_t>();
        earlierSeconds = state.read<double>();
        if (sppDone > targetSpp)
            throw NoriException("{} does not fit this render: {} samples per pixel done of {}",
                                options.resumeName, sppDone, targetSpp);
        if (!(earlierSeconds >= 0.0) || !std::isfinite(earlierSeconds))
            throw NoriException("{} is corrupt: it says {} s were spent", options.resumeName,
                                earlierSeconds);
        film.loadState(state);
        scene.getIntegrator()->loadState(state);
        if (!state.atEnd())
            throw NoriException("{} does not fit this render: bytes are left over",
                                options.resumeName);
        result.resumedSamplesPerPixel = sppDone;
    }
    auto totalSeconds = [&] { return earlierSeconds + elapsedSeconds(); };
    const size_t sppAtStart = sppDone;
    auto lastCheckpoint = std::chrono::steady_clock::now();
    size_t checkpointSpp = sppDone;
    // The state between two passes: what a resumed render reads back above.
    auto writeCheckpoint = [&] {
        StateWriter state;
        state.write<uint64_t>(sppDone);
        state.write<uint64_t>(result.passes);
        state.write<uint64_t>(result.samplesTaken);
        state.write<uint64_t>(result.invalidSamples);
        state.write<uint64_t>(samplesDone);
        state.write(totalSeconds());
        film.saveState(state);
        scene.getIntegrator()->saveState(state);
        options.checkpoint(state.bytes());
        lastCheckpoint = std::chrono::steady_clock::now();
        checkpointSpp = sppDone;
    };

    while (sppDone < targetSpp && !isCancelled(options)) {
        // A resumed render whose budget its earlier runs spent stops before a pass.
        if (options.timeBudget > 0.0 && sppDone == sppAtStart && sppAtStart > 0 &&
            totalSeconds() >= options.timeBudget)
            break;
        Integrator *integrator = scene.getIntegrator();
        size_t passSize = std::min(
            scheduledPassSize(result.passes, options.minPassSamples, options.maxPassSamples),
            targetSpp - sppDone);
        if (integrator->maxSamplesPerPass() > 0)
            passSize = std::min(passSize, integrator->maxSamplesPerPass());
        if (splatting)
            passSize =
                std::min(passSize, std::max<size_t>(1, kSplattingSamplesPerPass / pixelCount));
        if (options.timeBudget > 0.0 && sppDone > sppAtStart) {
            // Shorten the pass to what the measured rate says fits in the budget left.
            // The rate from this run's passes alone; the budget left from the whole render.
            const double elapsed = totalSeconds();
            const double secondsPerSpp =
                secondsSince(passesStart) / static_cast<double>(sppDone - sppAtStart);
            const double sppLeft = (options.timeBudget - elapsed) / secondsPerSpp;
            if (sppLeft < 1.0)
                break;
            passSize = std::min(passSize, static_cast<size_t>(sppLeft));
        }
        const SampleRange range{static_cast<uint32_t>(options.firstSample + sppDone),
                                static_cast<uint32_t>(options.firstSample + sppDone + passSize)};

        threads.run([&] { integrator->beginPass(&scene, range.first, range.end); });

        std::vector<std::unique_ptr<FilmBlock>> passBlocks(film.blockCount());
        std::vector<std::vector<SplatBuffer::Record>> passSplats(film.blockCount());
        std::atomic<bool> interrupted{false};
        size_t passValid = 0, passInvalid = 0; // counted in the result once committed
        threads.run([&] {
            parallelForEach(size_t(0), film.blockCount(), [&](size_t index) {
                std::unique_ptr<FilmBlock> pass = film.makePassBlock(index);
                std::unique_ptr<Sampler> sampler = prototype->clone();
                std::unique_ptr<Sampler> decisionSampler;
                if (prototype->getMaxTolerance() > 0.0f) {
                    decisionSampler = prototype->clone();
                    decisionSampler->setSeed(hashValues(prototype->getSeed(), kDecisionStream));
                }
                size_t valid = 0, invalid = 0;
                if (!renderBlockPass(scene, *sampler, decisionSampler.get(), film, filterSampler,
                                     film.block(index), *pass, range, options, passSplats[index],
                                     valid, invalid)) {
                    interrupted = true;
                    return;
                }
                std::lock_guard<std::mutex> lock(mutex);
                passValid += valid;
                passInvalid += invalid;
                samplesDone += static_cast<size_t>(pass->size().prod()) * passSize;
                if (options.progress)
                    options.progress(samplesDone, pixelCount * targetSpp);
                passBlocks[index] = std::move(pass);
            });
        });
        if (interrupted)
            break; // the unfinished pass is dropped: the film keeps whole passes only

        const Sampler &settings = *prototype;
        threads.run([&] {
            parallelFor(size_t(0), film.blockCount(), [&](size_t index) {
                FilmBlock &block = film.block(index);
                block.add(*passBlocks[index]);
                if (settings.getMaxTolerance() > 0.0f)
                    block.updateConvergence(settings.getMinSamples(), settings.getMaxTolerance());
            });
        });
        if (splatting)
            threads.run([&] { film.addSplats(passSplats); });
        threads.run([&] { integrator->endPass(&scene); });
        sppDone += passSize;
        ++result.passes;
        result.samplesTaken += passValid;
        result.invalidSamples += passInvalid;
        if (options.passFinished)
            options.passFinished(film, {result.passes, sppDone, targetSpp, totalSeconds()});
        if (film.convergedPixels() == pixelCount)
            break; // adaptive sampling stopped every pixel
        if (options.checkpoint && sppDone < targetSpp &&
            secondsSince(lastCheckpoint) >= options.checkpointSeconds)
            writeCheckpoint();
    }
    // Cancelled (Ctrl-C): the passes finished since the last checkpoint are kept too.
    if (options.checkpoint && isCancelled(options) && sppDone > checkpointSpp &&
        sppDone < targetSpp)
        writeCheckpoint();

    result.cancelled = isCancelled(options);
    result.samplesPerPixel = sppDone;
    result.complete =
        !result.cancelled && (sppDone == targetSpp || film.convergedPixels() == pixelCount);
    result.convergedPixels = film.convergedPixels();
    result.seconds = totalSeconds();
    result.layers = film.develop(options.keepFilterWeights);
    result.image = result.layers.layer("");
    return result;
}

} // namespace nori
