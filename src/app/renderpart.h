// A render split over processes or machines (a Slurm job array): part K of N takes the
// K-th of N disjoint slices of every pixel's sample indices, so the N parts together take
// exactly the full render's samples; each writes an EXR with its filter weights and a
// header naming what it is a part of, and mergeParts() sums the parts' filtered sums.
#pragma once

#include <nori/layeredimage.h>
#include <nori/render.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace nori {

class Scene;

/// "K/N": part K (1-based) of N.
struct PartSpec {
    int index = 0;
    int count = 0;
};

/// Parses "K/N" with 1 ≤ K ≤ N; throws NoriException naming `where` otherwise.
PartSpec parsePartSpec(const std::string &text, const std::string &where);

/// The sample indices of a part: [first, first + count).
struct SampleSlice {
    uint32_t first = 0;
    uint32_t count = 0;
};

/// Part K of N of a render of `totalSpp` samples per pixel: indices
/// [⌊(K−1)·S/N⌋, ⌊K·S/N⌋), so the slices tile [0, S) and differ in size by at most one.
/// Throws when N exceeds S (a part would take no sample).
SampleSlice partSamples(const PartSpec &part, size_t totalSpp);

/// What makes two processes render the same image: the digests of every file loading
/// the scene read (ReadFileRecorder), the -D definitions and the --convention.
/// Returned as 16 hex digits.
std::string sceneHash(const std::set<uint64_t> &fileDigests,
                      const std::map<std::string, std::string> &defines,
                      const std::string &convention);

/// The header of a part's EXR (attributes "nori.part", "nori.sceneHash", ...).
struct PartHeader {
    PartSpec part;
    std::string sceneHash;
    Eigen::Vector2i resolution{0, 0};
    size_t totalSamplesPerPixel = 0;
    SampleSlice samples;
    std::string filter; ///< the reconstruction filter, as its toString() says
    std::string scene;  ///< the scene file's name, for people reading the header
};

/// Writes `header` into the image's attributes.
void writePartHeader(const PartHeader &header, LayeredImage &image);
/// Reads the header of a part's image; throws NoriException naming `file` when an
/// attribute is missing or malformed, or the image lacks the merge's weight channel.
PartHeader readPartHeader(const LayeredImage &image, const std::string &file);

/// Renders part `part` of the scene (options.samplesPerPixel: the whole render's spp, 0
/// for the sampler's own) with the weights the merge needs, its header written into
/// result.layers. Throws for renders that cannot be split: adaptive sampling (where a
/// pixel stops depends on all its earlier samples) and a time budget.
RenderResult renderPart(Scene &scene, RenderOptions options, const PartSpec &part,
                        const std::string &sceneHash, const std::string &sceneName);

struct MergeResult {
    LayeredImage image;         ///< beauty and AOV layers, as one process would write them
    int partCount = 0;          ///< N
    std::vector<int> missing;   ///< parts not given (only with allowMissing)
    size_t samplesPerPixel = 0; ///< samples of the parts merged
    size_t totalSamplesPerPixel = 0;
};

/// Merges part EXR files: every filtered layer as Σ(value·weight)/Σweight over the parts
/// (the sums a single film would have held), sample counts summed, the variance layer
/// recomputed from the merged half-buffers. Parts are read one at a time. Throws
/// NoriException naming the part when one is not a part, belongs to another render
/// (scene hash, spp, resolution, filter, N, layers), repeats a K, or when parts are
/// missing and `allowMissing` is false.
MergeResult mergeParts(const std::vector<std::string> &files, bool allowMissing);

} // namespace nori
