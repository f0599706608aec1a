// The scenes the denoiser is measured on, shared by its tests and nori-bench-denoiser,
// which also renders their committed references (tests/data/denoiser/<name>.exr).
#pragma once

#include <nori/bitmap.h>
#include <nori/parser.h>
#include <nori/scene.h>

#include <algorithm>
#include <string>
#include <vector>

namespace nori::denoiserscenes {

struct DenoiserScene {
    std::string name;      ///< the reference is tests/data/denoiser/<name>.exr
    std::string file;      ///< relative to the repository
    Defines defines;       ///< small sizes, so that a converged reference is cheap
    std::string reference; ///< another entry's reference, when the scene is the same
};

/// The references are rendered with seed 0 at this many samples per pixel; noisy images
/// use other seeds, so they share no samples with them.
constexpr int kReferenceSpp = 8192;

/// The Cornell box (with its glass sphere; path_mis, as its reference), Veach's MIS plates (direct_mis) and the
/// textured scene (image textures, normal maps, a mirror sphere).
inline const std::vector<DenoiserScene> &scenes() {
    static const std::vector<DenoiserScene> list{
        {"cbox", "scenes/cbox/cbox.xml", {{"size", "128"}, {"integrator", "path_mis"}}, ""},
        {"veach", "scenes/veach/veach.xml", {{"width", "160"}, {"height", "96"}}, ""},
        {"textured", "scenes/textured/textured.xml", {{"width", "160"}, {"height", "90"}}, ""},
    };
    return list;
}

/// The README's default scene as it renders by default (the progressive photon mapper at
/// the scene's 12 spp), at the size of the Cornell box entry, whose reference it shares:
/// the same scene, converged.
inline const DenoiserScene &defaultScene() {
    static const DenoiserScene entry{"default", "scenes/cbox/cbox.xml", {{"size", "128"}}, "cbox"};
    return entry;
}

/// The path of an entry's converged reference in the repository at `sourceDir`.
inline std::string referencePath(const DenoiserScene &entry, const std::string &sourceDir) {
    return sourceDir + "/tests/data/denoiser/" +
           (entry.reference.empty() ? entry.name : entry.reference) + ".exr";
}

using PixelMask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The pixels whose camera ray first hits an emitter (an `emission` layer, AOV::Emission,
/// not black), grown by `rim` pixels: where the light's own coverage noise is, which no
/// feature explains.
inline PixelMask emitterPixels(const Bitmap &emission, int rim) {
    PixelMask mask = PixelMask::Constant(emission.rows(), emission.cols(), false);
    for (int y = 0; y < emission.height(); ++y)
        for (int x = 0; x < emission.width(); ++x)
            if ((emission(y, x) > 0.0f).any())
                for (int dy = -rim; dy <= rim; ++dy)
                    for (int dx = -rim; dx <= rim; ++dx)
                        if (y + dy >= 0 && y + dy < emission.height() && x + dx >= 0 &&
                            x + dx < emission.width())
                            mask(y + dy, x + dx) = true;
    return mask;
}

/// Fireflies smeared by a denoiser: the pixels of `denoised` brighter (in luminance) than
/// the 99.9th percentile of `noisy` where `reference` is not, among the pixels of `mask`
/// (the percentile too). The mask leaves out the emitters' own pixels: a light seen
/// directly fills the top of the histogram with its own radiance, and its pixels match
/// the reference to rounding, above or below it.
inline size_t smearedFireflies(const Bitmap &noisy, const Bitmap &denoised, const Bitmap &reference,
                               const PixelMask &mask) {
    std::vector<float> luminances;
    for (int y = 0; y < noisy.height(); ++y)
        for (int x = 0; x < noisy.width(); ++x)
            if (mask(y, x))
                luminances.push_back(noisy(y, x).getLuminance());
    if (luminances.empty())
        return 0;
    const size_t rank = luminances.size() * 999 / 1000;
    std::nth_element(luminances.begin(), luminances.begin() + rank, luminances.end());
    const float threshold = luminances[rank];
    size_t count = 0;
    for (int y = 0; y < noisy.height(); ++y)
        for (int x = 0; x < noisy.width(); ++x)
            if (mask(y, x) && denoised(y, x).getLuminance() > threshold &&
                reference(y, x).getLuminance() <= threshold)
                ++count;
    return count;
}

/// Loads a scene of the list from the repository at `sourceDir`, at `spp` samples per
/// pixel (0: the scene's own) with `seed`; `overrides` win over the entry's own defines
/// (a larger size).
inline std::shared_ptr<Scene> load(const DenoiserScene &entry, const std::string &sourceDir,
                                   int spp, int seed, Defines overrides = {}) {
    for (const auto &[name, value] : entry.defines)
        overrides.emplace(name, value);
    if (spp > 0)
        overrides["spp"] = std::to_string(spp);
    overrides["seed"] = std::to_string(seed);
    auto scene = std::dynamic_pointer_cast<Scene>(
        loadFromXML(sourceDir + "/" + entry.file, LoadOptions(overrides)));
    if (!scene)
        throw NoriException("{}: not a scene", entry.file);
    return scene;
}

} // namespace nori::denoiserscenes
