// The scenes the denoiser is measured on, shared by its tests and nori-bench-denoiser,
// which also renders their committed references (tests/data/denoiser/<name>.exr).
#pragma once

#include <nori/parser.h>
#include <nori/scene.h>

#include <string>
#include <vector>

namespace nori::denoiserscenes {

struct DenoiserScene {
    std::string name; ///< the reference is tests/data/denoiser/<name>.exr
    std::string file; ///< relative to the repository
    Defines defines;  ///< small sizes, so that a converged reference is cheap
};

/// The references are rendered with seed 0 at this many samples per pixel; noisy images
/// use other seeds, so they share no samples with them.
constexpr int kReferenceSpp = 8192;

/// The Cornell box (with its glass sphere; path_mis, as its reference), Veach's MIS plates (direct_mis) and the
/// textured scene (image textures, normal maps, a mirror sphere).
inline const std::vector<DenoiserScene> &scenes() {
    static const std::vector<DenoiserScene> list{
        {"cbox", "scenes/cbox/cbox.xml", {{"size", "128"}, {"integrator", "path_mis"}}},
        {"veach", "scenes/veach/veach.xml", {{"width", "160"}, {"height", "96"}}},
        {"textured", "scenes/textured/textured.xml", {{"width", "160"}, {"height", "90"}}},
    };
    return list;
}

/// Loads a scene of the list from the repository at `sourceDir`, at `spp` samples per
/// pixel with `seed`; `overrides` win over the entry's own defines (a larger size).
inline std::shared_ptr<Scene> load(const DenoiserScene &entry, const std::string &sourceDir,
                                   int spp, int seed, Defines overrides = {}) {
    for (const auto &[name, value] : entry.defines)
        overrides.emplace(name, value);
    overrides["spp"] = std::to_string(spp);
    overrides["seed"] = std::to_string(seed);
    auto scene = std::dynamic_pointer_cast<Scene>(
        loadFromXML(sourceDir + "/" + entry.file, LoadOptions(overrides)));
    if (!scene)
        throw NoriException("{}: not a scene", entry.file);
    return scene;
}

} // namespace nori::denoiserscenes
