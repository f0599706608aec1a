// Split renders (renderpart.h): the slices of sample indices, the parts' headers, and
// merges that equal the single-process render.
#include "testutil.h"

#include "app/renderpart.h"
#include <nori/aov.h>
#include <nori/bbox.h>
#include <nori/filesystem.h>
#include <nori/parser.h>

#include <catch2/catch.hpp>

#include <cmath>

using namespace nori;
using namespace nori::testing;

namespace {

constexpr size_t kSpp = 16;
constexpr int kParts = 4;
const std::vector<AOV> kAllAOVs = {AOV::Albedo,   AOV::Normal,      AOV::Depth,
                                   AOV::Position, AOV::SampleCount, AOV::Variance};

/// The Cornell box of the README (glass sphere: caustic fireflies, large values), small.
std::shared_ptr<Scene> loadBox(const std::string &seed = "0") {
    LoadOptions options({{"integrator", "path_mis"},
                         {"size", "40"},
                         {"spp", std::to_string(kSpp)},
                         {"seed", seed}});
    return std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml", options));
}

RenderOptions partOptions() {
    RenderOptions options = quietOptions(2);
    options.aovs = kAllAOVs;
    return options;
}

/// Renders parts `which` of kParts of the box into dir/part<K>.exr; returns the files.
std::vector<std::string> renderParts(Scene &scene, const TempDir &dir,
                                     const std::vector<int> &which,
                                     const std::string &hash = "0123456789abcdef") {
    std::vector<std::string> files;
    for (int k : which) {
        const RenderResult part = renderPart(scene, partOptions(), {k, kParts}, hash, "cbox.xml");
        files.push_back((dir.path() / fmt::format("part{}.exr", k)).string());
        part.layers.saveEXR(files.back());
    }
    return files;
}

/// The largest difference of a merged channel from the single render's, in units of its
/// float-summation bound. A pixel of the film sums n = spp·(2r+1)² splats in float (r the
/// filter radius in pixels) in some order; any order's error is at most (n−1)·u·Σ|terms|
/// (Higham, "Accuracy and Stability of Numerical Algorithms", §4.2; u = 2⁻²⁴), and the
/// two renders add theirs in different orders: so |merged − single| ≤ 2(n−1)·u·S, with S
/// the filtered mean of |sample| — the pixel's value for the non-negative layers (beauty,
/// albedo, depth), and the bound of |sample| for signed ones (1 for a normal, the scene's
/// extent for a position). The variance (A − B)²/4 of the half means moves by at most
/// |A − B|·(|dA| + |dB|)/2 ≤ √var · 4(n−1)·u·(A + B).
double worstErrorInBounds(const LayeredImage &merged, const LayeredImage &single, double terms,
                          float sceneExtent) {
    const double u = std::ldexp(1.0, -24);
    const double scale = 2.0 * (terms - 1.0) * u;
    const LayeredImage::Channel &red = single.channels().at("R");
    double worst = 0.0;
    for (const auto &[name, values] : single.channels()) {
        const LayeredImage::Channel &other = merged.channels().at(name);
        const std::string layer =
            name.substr(0, name.find('.') == std::string::npos ? 0 : name.find('.'));
        for (int y = 0; y < values.rows(); ++y)
            for (int x = 0; x < values.cols(); ++x) {
                const double difference = std::abs(double(other(y, x)) - values(y, x));
                double bound;
                if (layer == "sampleCount")
                    bound = 0.0; // whole numbers, summed exactly
                else if (layer == "normal")
                    bound = scale * 1.0;
                else if (layer == "position")
                    bound = scale * sceneExtent;
                else if (layer == "variance")
                    bound = 2.0 * scale * std::sqrt(double(values(y, x))) * 4.0 *
                            std::abs(double(red(y, x)));
                else
                    bound = scale * std::abs(double(values(y, x)));
                // Plus the rounding of the stored floats (value·weight and the division).
                bound += 4.0 * u * std::abs(double(values(y, x)));
                if (difference > 0.0)
                    worst = std::max(worst, bound > 0.0 ? difference / bound : INFINITY);
            }
    }
    return worst;
}

} // namespace

TEST_CASE("The slices of a split render tile every pixel's sample indices", "[parts]") {
    for (size_t spp = 1; spp <= 40; ++spp)
        for (int n = 1; n <= static_cast<int>(spp); ++n) {
            uint32_t next = 0;
            for (int k = 1; k <= n; ++k) {
                const SampleSlice slice = partSamples({k, n}, spp);
                REQUIRE(slice.first == next);
                REQUIRE(slice.count >= spp / n);
                REQUIRE(slice.count <= spp / n + 1);
                next = slice.first + slice.count;
            }
            REQUIRE(next == spp);
        }
    CHECK_THAT(errorOf([] {
                   partSamples({1, 5}, 4);
               }),
               Catch::Contains("cannot split 4 samples per pixel into 5 parts"));
}

TEST_CASE("Part specifications K/N are parsed strictly", "[parts]") {
    CHECK(parsePartSpec("3/4", "--part").index == 3);
    CHECK(parsePartSpec("3/4", "--part").count == 4);
    CHECK(parsePartSpec("1/1", "--part").count == 1);
    for (const char *bad : {"0/4", "5/4", "4", "/4", "1/", "a/b", "-1/4", "1/4x", " 1/4", "1/0",
                            "99999999999999999999/1"})
        CHECK_THAT(errorOf([&] { parsePartSpec(bad, "--part"); }),
                   Catch::Contains("--part expects K/N") && Catch::Contains(bad));
}

TEST_CASE("Four parts merged equal the single-process render", "[parts]") {
    std::shared_ptr<Scene> scene = loadBox();
    RenderOptions options = partOptions();
    const RenderResult single = renderScene(*scene, options);
    TempDir dir;
    const std::vector<std::string> files = renderParts(*scene, dir, {1, 2, 3, 4});

    const MergeResult merged = mergeParts(files, false);
    CHECK(merged.samplesPerPixel == kSpp);
    CHECK(merged.missing.empty());
    // The same layers as the single render, no more (no weights, no half-buffer).
    std::vector<std::string> singleChannels, mergedChannels;
    for (const auto &[name, values] : single.layers.channels())
        singleChannels.push_back(name);
    for (const auto &[name, values] : merged.image.channels())
        mergedChannels.push_back(name);
    CHECK(mergedChannels == singleChannels);

    // Not bit-identical: the single render adds its passes (1, 1, 2, 4, 8 spp) and each
    // part its own 4 samples in float, so the same samples are summed in another order.
    // Within the float-summation bound instead.
    const BoundingBox3f bounds = scene->getBoundingBox();
    const float extent =
        std::max(bounds.min.cwiseAbs().maxCoeff(), bounds.max.cwiseAbs().maxCoeff());
    const float radius = scene->getCamera()->getReconstructionFilter()->getRadius();
    const double terms = double(kSpp) * std::pow(2.0 * std::ceil(radius) + 1.0, 2.0);
    const double worst = worstErrorInBounds(merged.image, single.layers, terms, extent);
    INFO("worst difference: " << worst << " of its bound (" << terms << " terms a pixel)");
    CHECK(worst <= 1.0);
    WARN("merged vs single: worst difference " << worst << " of its bound");

    SECTION("and the bound is tight enough to tell a part missing or of another seed") {
        const MergeResult three = mergeParts({files[0], files[1], files[2]}, true);
        CHECK(three.missing == std::vector<int>{4});
        CHECK(three.samplesPerPixel == 12);
        const double missing = worstErrorInBounds(three.image, single.layers, terms, extent);
        WARN("a part missing: " << missing);
        CHECK(missing > 100.0);

        std::shared_ptr<Scene> otherSeed = loadBox("1");
        const std::vector<std::string> swapped =
            renderParts(*otherSeed, dir, {4}); // overwrites part4.exr
        const MergeResult mixed = mergeParts(files, false);
        const double mixedError = worstErrorInBounds(mixed.image, single.layers, terms, extent);
        WARN("a part of another seed: " << mixedError);
        CHECK(mixedError > 100.0);
    }
}

TEST_CASE("One part of one is the single render, bit for bit but the variance", "[parts]") {
    // Part 1/1 renders the same passes in the same order; the merge's value·weight/weight
    // in double is exact (a product of two floats fits a double's 53 bits). The variance
    // is recomputed from sums rebuilt as mean·weight, which the float mean has rounded.
    std::shared_ptr<Scene> scene = loadBox();
    const RenderResult single = renderScene(*scene, partOptions());
    TempDir dir;
    const RenderResult part = renderPart(*scene, partOptions(), {1, 1}, "0123456789abcdef", "cbox");
    const std::string file = (dir.path() / "part.exr").string();
    part.layers.saveEXR(file);
    const MergeResult merged = mergeParts({file}, false);
    for (const auto &[name, values] : single.layers.channels()) {
        INFO(name);
        if (name.rfind("variance.", 0) != 0)
            CHECK((merged.image.channels().at(name) == values).all());
    }
    // The rebuilt sum fl(S/W)·W is within u·S of S: the bound of a two-term float sum.
    const double terms = 2.0;
    CHECK(worstErrorInBounds(merged.image, single.layers, terms, 1.0f) <= 1.0);
}

TEST_CASE("The merge refuses parts of other renders, twice-given and missing parts", "[parts]") {
    std::shared_ptr<Scene> scene = loadBox();
    TempDir dir;
    const std::vector<std::string> files = renderParts(*scene, dir, {1, 2, 3, 4});

    CHECK_THAT(errorOf([&] {
                   mergeParts({files[0], files[1], files[3]}, false);
               }),
               Catch::Contains("1 of 4 parts missing (part 3)") &&
                   Catch::Contains("--allow-missing"));
    CHECK_THAT(errorOf([&] {
                   mergeParts({files[0], files[2], files[0]}, false);
               }),
               Catch::Contains(files[0] + ": part 1/4 given twice"));

    // Another scene hash: the part names itself.
    RenderResult foreign =
        renderPart(*scene, partOptions(), {2, kParts}, "fedcba9876543210", "cbox.xml");
    const std::string foreignFile = (dir.path() / "foreign.exr").string();
    foreign.layers.saveEXR(foreignFile);
    CHECK_THAT(
        errorOf([&] {
            mergeParts({files[0], foreignFile, files[2], files[3]}, false);
        }),
        Catch::Contains(foreignFile + ": scene hash fedcba9876543210 differs from " + files[0]));

    // Another spp: a part of the 32-spp render.
    RenderOptions more = partOptions();
    more.samplesPerPixel = 2 * kSpp;
    RenderResult other = renderPart(*scene, more, {2, kParts}, "0123456789abcdef", "cbox.xml");
    const std::string otherFile = (dir.path() / "spp.exr").string();
    other.layers.saveEXR(otherFile);
    CHECK_THAT(errorOf([&] {
                   mergeParts({files[0], otherFile}, false);
               }),
               Catch::Contains(otherFile + ": total spp 32 differs from"));

    // Other AOV layers.
    RenderOptions fewer = quietOptions(2);
    RenderResult plain = renderPart(*scene, fewer, {2, kParts}, "0123456789abcdef", "cbox.xml");
    const std::string plainFile = (dir.path() / "plain.exr").string();
    plain.layers.saveEXR(plainFile);
    CHECK_THAT(errorOf([&] {
                   mergeParts({files[0], plainFile}, false);
               }),
               Catch::Contains(plainFile + ": channels") && Catch::Contains("other AOV layers"));

    // A render that is not a part at all.
    const RenderResult whole = renderScene(*scene, partOptions());
    const std::string wholeFile = (dir.path() / "whole.exr").string();
    whole.layers.saveEXR(wholeFile);
    CHECK_THAT(errorOf([&] { mergeParts({wholeFile}, false); }),
               Catch::Contains(wholeFile + ": not a part of a split render"));
}

TEST_CASE("Renders that cannot be split say why", "[parts]") {
    std::shared_ptr<Scene> scene = loadBox();
    RenderOptions timed = partOptions();
    timed.timeBudget = 1.0;
    CHECK_THAT(errorOf([&] {
                   renderPart(*scene, timed, {1, 2}, "0", "cbox");
               }),
               Catch::Contains("cannot have a time budget"));
    LoadOptions adaptive({{"integrator", "path_mis"}, {"size", "8"}, {"tolerance", "0.1"}});
    auto adaptiveScene = std::dynamic_pointer_cast<Scene>(
        loadFromXML(std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml", adaptive));
    CHECK_THAT(errorOf([&] {
                   renderPart(*adaptiveScene, partOptions(), {1, 2}, "0", "cbox");
               }),
               Catch::Contains("adaptive sampling"));
}

TEST_CASE("The scene hash covers every file read, the definitions and the convention", "[parts]") {
    TempDir dir;
    const std::string mesh = dir.write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    const std::string xml = dir.write("scene.xml", R"(<scene>
        <integrator type="normals"/><camera type="perspective"/>
        <mesh type="obj"><string name="filename" value="quad.obj"/></mesh></scene>)");
    const auto hashOf = [&](const Defines &defines, const std::string &convention) {
        ReadFileRecorder recorder;
        LoadOptions options(defines);
        options.convention = convention;
        loadFromXML(xml, options);
        CHECK(recorder.digests().size() == 2); // the XML file and the mesh
        return sceneHash(recorder.digests(), defines, convention);
    };
    const std::string base = hashOf({}, "");
    CHECK(base.size() == 16);
    CHECK(hashOf({}, "") == base);
    CHECK(hashOf({{"x", "1"}}, "") != base);
    CHECK(hashOf({}, "eth") != base);
    dir.write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1.5 0\nf 1 2 3\n"); // the mesh changed
    CHECK(hashOf({}, "") != base);
}

TEST_CASE("nori --part and nori merge from the command line", "[parts][cli]") {
    TempDir dir;
    const std::string scene = std::string(NORI_SOURCE_DIR) + "/scenes/cbox/cbox.xml";
    const auto part = [&](int k, const std::string &seed) {
        const std::string out = (dir.path() / fmt::format("p{}s{}", k, seed)).string();
        const ProcessResult result =
            runNori({"--no-progress", "-D", "integrator=path_mis", "-D", "size=16", "-D", "spp=4",
                     "-D", "seed=" + seed, "--part", fmt::format("{}/2", k), "--aovs", "variance",
                     "-o", out, scene});
        INFO(result.output);
        REQUIRE(result.exitCode == 0);
        CHECK_THAT(result.output,
                   Catch::Contains(fmt::format("Part {} of 2: sample indices {} to {}", k,
                                               2 * (k - 1), 2 * k - 1)));
        return out + ".exr";
    };
    const std::string first = part(1, "0"), second = part(2, "0"), otherSeed = part(2, "1");
    const std::string merged = (dir.path() / "merged").string();

    ProcessResult ok = runNori({"merge", first, second, "-o", merged});
    INFO(ok.output);
    CHECK(ok.exitCode == 0);
    CHECK_THAT(ok.output, Catch::Contains("Merged 2 parts (4 spp)"));
    const LayeredImage image = LayeredImage::loadEXR(merged + ".exr");
    CHECK(image.hasLayer("variance"));
    // The half-buffers stay, so that the merged image can be compared (nori-imgtool compare).
    CHECK(image.channels().count("weight.W"));
    CHECK(image.hasLayer("evenHalf"));
    CHECK(image.attributes.at("nori.mergedParts") == "2 of 2");
    CHECK(std::filesystem::exists(merged + ".png"));

    // -D seed=1 changes the scene: its hash differs, and the part names itself.
    ProcessResult mixed = runNori({"merge", first, otherSeed, "-o", merged});
    CHECK(mixed.exitCode == 1);
    CHECK_THAT(mixed.output, Catch::Contains(otherSeed + ": scene hash"));

    ProcessResult missing = runNori({"merge", first, "-o", merged});
    CHECK(missing.exitCode == 1);
    CHECK_THAT(missing.output, Catch::Contains("1 of 2 parts missing (part 2)"));
    ProcessResult allowed = runNori({"merge", first, "-o", merged, "--allow-missing"});
    CHECK(allowed.exitCode == 0);
    CHECK_THAT(allowed.output, Catch::Contains("Warning: merged 2 of 4 spp; missing part 2 of 2"));
}
