// Writes the seed corpus of the checkpoint fuzz target (tests/fuzz/corpus/checkpoint): the
// checkpoints of the scene of checkpoint_scene.h after each of its passes, made by the
// render loop and the checkpoint writer themselves.
//   nori-make-checkpoint-corpus tests/fuzz/corpus/checkpoint
#include "app/checkpoint.h"
#include "checkpoint_scene.h"
#include <nori/filesystem.h>
#include <nori/parser.h>
#include <nori/render.h>
#include <nori/scene.h>

#include <cstdio>

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: nori-make-checkpoint-corpus DIRECTORY\n");
        return 2;
    }
    try {
        auto scene = std::dynamic_pointer_cast<nori::Scene>(
            nori::loadFromXMLString(nori::fuzz::kCheckpointScene));
        nori::CheckpointIdentity identity;
        identity.version = "fuzz";
        identity.sceneHash = "0000000000000000";
        int pass = 0;
        nori::RenderOptions options;
        options.threads = 1;
        options.aovs = nori::fuzz::checkpointAOVs();
        options.checkpointSeconds = 0.0;
        options.checkpoint = [&](const std::string &state) {
            nori::writeBinaryFile(std::string(argv[1]) + "/pass-" + std::to_string(++pass) +
                                      ".checkpoint",
                                  nori::encodeCheckpoint(identity, state), "checkpoint");
        };
        nori::renderScene(*scene, options);
    } catch (const nori::NoriException &error) {
        std::fprintf(stderr, "nori-make-checkpoint-corpus: %s\n", error.what());
        return 1;
    }
    return 0;
}
