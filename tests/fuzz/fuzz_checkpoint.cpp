// libFuzzer target of checkpoint files (src/app/checkpoint.h) and of the render state in
// them: the input is read as a checkpoint and the small scene of checkpoint_scene.h
// resumed from its state; it must render or end in a NoriException.
#include "app/checkpoint.h"
#include "checkpoint_scene.h"
#include <nori/parser.h>
#include <nori/render.h>
#include <nori/scene.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        const nori::Checkpoint checkpoint = nori::readCheckpoint(bytes, "fuzz.checkpoint");
        // Loaded once: path_mis keeps no state between renders (its loadState reads none).
        static const std::shared_ptr<nori::Scene> scene = std::dynamic_pointer_cast<nori::Scene>(
            nori::loadFromXMLString(nori::fuzz::kCheckpointScene));
        nori::RenderOptions options;
        options.threads = 1;
        options.aovs = nori::fuzz::checkpointAOVs();
        options.resumeState = &checkpoint.state;
        const nori::RenderResult result = nori::renderScene(*scene, options);
        if (result.samplesPerPixel != 8 && !result.cancelled && result.convergedPixels == 0)
            __builtin_trap(); // a resumed render renders up to the sampler's count
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
