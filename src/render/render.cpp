#include <nori/imageblock.h>
#include <nori/progress.h>
#include <nori/render.h>
#include <nori/scene.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <mutex>

namespace nori {

namespace {

constexpr int kBlockSize = 32;

struct BlockRegion {
    Point2i offset;
    Vector2i size;
};

/// Splits the image into kBlockSize² blocks, row by row.
std::vector<BlockRegion> makeBlocks(const Vector2i &imageSize) {
    std::vector<BlockRegion> blocks;
    for (int y = 0; y < imageSize.y(); y += kBlockSize)
        for (int x = 0; x < imageSize.x(); x += kBlockSize)
            blocks.push_back({Point2i(x, y), Vector2i(std::min(kBlockSize, imageSize.x() - x),
                                                      std::min(kBlockSize, imageSize.y() - y))});
    return blocks;
}

bool isCancelled(const RenderOptions &options) {
    return options.cancel && options.cancel->load(std::memory_order_relaxed);
}

/// Renders one block; returns false when cancelled part-way (the block is discarded).
bool renderBlock(const Scene &scene, Sampler &sampler, ImageBlock &block,
                 const RenderOptions &options, size_t &invalidSamples) {
    const Integrator *integrator = scene.getIntegrator();
    const Point2i &offset = block.getOffset();
    const Vector2i &size = block.getSize();

    block.clear();
    sampler.prepare(block);
    for (int y = 0; y < size.y(); ++y) {
        for (int x = 0; x < size.x(); ++x) {
            const Point2i pixel(offset.x() + x, offset.y() + y);
            sampler.generate(pixel);
            for (size_t i = 0; i < sampler.getSampleCount(); ++i) {
                // Checked every sample (a relaxed load costs nothing next to a path), so
                // Ctrl-C is prompt even at millions of samples per pixel.
                if (isCancelled(options))
                    return false;
                Point2f pixelSample = pixel.cast<float>() + sampler.next2D();
                Point2f apertureSample = sampler.next2D();
                Ray3f ray;
                Color3f value = scene.sampleCameraRay(ray, pixelSample, apertureSample);
                // A weight of zero (a lens blocked the ray) leaves the ray unset: no light.
                if (!(value == 0.0f).all())
                    value *= integrator->Li(&scene, &sampler, ray);
                if (value.isValid())
                    block.put(pixelSample, value);
                else
                    ++invalidSamples;
                sampler.advance();
            }
        }
    }
    return true;
}

} // namespace

int defaultThreadCount() {
    return tbb::this_task_arena::max_concurrency();
}

RenderResult renderScene(Scene &scene, const RenderOptions &options) {
    const Camera *camera = scene.getCamera();
    const Vector2i outputSize = camera->getOutputSize();
    const ReconstructionFilter *filter = camera->getReconstructionFilter();

    std::unique_ptr<Sampler> prototype = scene.getSampler()->clone();
    if (options.samplesPerPixel > 0)
        prototype->setSampleCount(options.samplesPerPixel);

    scene.getIntegrator()->preprocess(&scene);

    const std::vector<BlockRegion> regions = makeBlocks(outputSize);
    RenderResult result;
    result.blocksTotal = regions.size();
    result.samplesPerPixel = prototype->getSampleCount();

    // Finished blocks are merged in index order (the next one as soon as its
    // predecessors are in), so every pixel sums its contributions in the same order.
    ImageBlock image(outputSize, filter);
    std::vector<std::unique_ptr<ImageBlock>> finished(regions.size());
    size_t nextToMerge = 0;
    std::mutex mutex;
    ProgressBar progress("Rendering", regions.size(), options.showProgress);

    auto renderRange = [&](const tbb::blocked_range<size_t> &range) {
        for (size_t index = range.begin(); index != range.end(); ++index) {
            if (isCancelled(options))
                return;
            auto block = std::make_unique<ImageBlock>(regions[index].size, filter);
            block->setOffset(regions[index].offset);
            std::unique_ptr<Sampler> sampler = prototype->clone();
            size_t invalid = 0;
            if (!renderBlock(scene, *sampler, *block, options, invalid))
                return;

            std::lock_guard<std::mutex> lock(mutex);
            finished[index] = std::move(block);
            result.invalidSamples += invalid;
            result.samplesTaken +=
                static_cast<size_t>(regions[index].size.prod()) * prototype->getSampleCount();
            ++result.blocksDone;
            while (nextToMerge < finished.size() && finished[nextToMerge]) {
                image.put(*finished[nextToMerge]);
                finished[nextToMerge].reset();
                ++nextToMerge;
            }
            progress.update(result.blocksDone);
        }
    };

    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, regions.size(), 1), renderRange,
                          tbb::simple_partitioner());
    });

    // After a cancellation, blocks past a gap are still waiting: merge them in order.
    for (; nextToMerge < finished.size(); ++nextToMerge)
        if (finished[nextToMerge])
            image.put(*finished[nextToMerge]);

    progress.finish();
    result.complete = result.blocksDone == result.blocksTotal;
    result.seconds = progress.elapsedSeconds();
    result.image = image.toBitmap();
    return result;
}

} // namespace nori
