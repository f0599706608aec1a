// The progressive render loop: images independent of thread count and pass schedule,
// time budgets, AOV layers (albedo, normal, depth, position, sampleCount, variance),
// multi-layer EXR and PFM files, adaptive sampling, and integrator t-tests under the
// stratified and Sobol' samplers.
#include <nori/filesystem.h>
#include <nori/film.h>
#include <nori/imagefile.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/render.h>
#include <nori/rfilter.h>
#include <nori/scene.h>
#include <nori/statistics.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::identicalImages;
using nori::testing::loadScene;
using nori::testing::quietOptions;
using nori::testing::TempDir;

namespace {

/// Spheres on a floor under ambient occlusion: a noisy image, with `sampler` and `filter`.
std::string aoScene(const std::string &sampler, int spp, const std::string &filter = "box",
                    int seed = 0, const std::string &samplerExtra = "") {
    return fmt::format(R"(<scene>
    <integrator type="ao"/>
    <sampler type="{}"><integer name="sampleCount" value="{}"/>
        <integer name="seed" value="{}"/>{}</sampler>
    <camera type="perspective">
        <integer name="width" value="40"/><integer name="height" value="30"/>
        <transform name="toWorld"><lookat origin="0,1,6" target="0,0.5,0"/></transform>
        <rfilter type="{}"/>
    </camera>
    <mesh type="sphere"><point name="center" value="0,1,0"/></mesh>
    <mesh type="sphere"><point name="center" value="1.5,0.5,0.5"/><float name="radius" value="0.5"/></mesh>
    <mesh type="sphere"><point name="center" value="0,-1000,0"/><float name="radius" value="1000"/></mesh>
</scene>)",
                       sampler, spp, seed, samplerExtra, filter);
}

/// The largest difference between two images relative to max(1, |value|).
float maxRelativeDifference(const Bitmap &a, const Bitmap &b) {
    float largest = 0.0f;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int c = 0; c < 3; ++c)
                largest = std::max(largest, std::abs(a(y, x)[c] - b(y, x)[c]) /
                                                std::max(1.0f, std::abs(a(y, x)[c])));
    return largest;
}

} // namespace

TEST_CASE("Every sampler renders the same image with one and two threads, AOVs too",
          "[render][progressive]") {
    for (const std::string sampler : {"independent", "stratified", "sobol"}) {
        CAPTURE(sampler);
        auto scene = loadScene(aoScene(sampler, 6, "gaussian"));
        RenderOptions one = quietOptions(1), two = quietOptions(2);
        one.aovs = two.aovs = parseAOVList("albedo,normal,depth,variance", "test");
        const RenderResult a = renderScene(*scene, one), b = renderScene(*scene, two);
        CHECK(a.passes == 4); // 1, 1, 2, 2 spp
        for (const std::string layer : {"", "albedo", "normal", "depth", "variance"}) {
            CAPTURE(layer);
            CHECK(identicalImages(a.layers.layer(layer), b.layers.layer(layer)));
        }
    }
}

TEST_CASE("The pass schedule changes an image only by float summation order",
          "[render][progressive]") {
    // 64 spp in passes of 1 spp, in the default 1, 1, 2, ..., 32, and in one pass: each
    // pixel sums 64 values in other groupings, so they differ by at most about 64 float
    // roundings of the pixel value: 64 · 2^-24 < 4·10^-6 relative. With a box filter
    // and one pass the order is the one of a single pass.
    for (const std::string filter : {"box", "gaussian"}) {
        CAPTURE(filter);
        auto scene = loadScene(aoScene("sobol", 64, filter));
        RenderOptions schedule = quietOptions(2);
        const RenderResult standard = renderScene(*scene, schedule);
        schedule.maxPassSamples = 1;
        const RenderResult single = renderScene(*scene, schedule);
        schedule.minPassSamples = schedule.maxPassSamples = 64;
        const RenderResult whole = renderScene(*scene, schedule);
        CHECK(standard.passes == 7);
        CHECK(single.passes == 64);
        CHECK(whole.passes == 1);
        CHECK(maxRelativeDifference(standard.image, single.image) < 4e-6f);
        CHECK(maxRelativeDifference(standard.image, whole.image) < 4e-6f);
        // And the images are not all the same trivially: another seed differs by far more.
        const RenderResult reseeded =
            renderScene(*loadScene(aoScene("sobol", 64, filter, 1)), quietOptions(2));
        CHECK(maxRelativeDifference(standard.image, reseeded.image) > 1e-2f);
    }
}

TEST_CASE("A time budget stops within one pass of it", "[render][progressive]") {
    // Millions of spp would take hours: the budget decides.
    auto scene = loadScene(aoScene("independent", 1 << 24));
    RenderOptions options = quietOptions(2);
    options.timeBudget = 1.0;
    std::vector<double> passEnds;
    options.passFinished = [&](const Film &, const PassReport &report) {
        passEnds.push_back(report.seconds);
    };
    const RenderResult result = renderScene(*scene, options);
    REQUIRE(passEnds.size() >= 3);
    CHECK_FALSE(result.complete);
    CHECK_FALSE(result.cancelled);
    double longestPass = passEnds.front();
    for (size_t i = 1; i < passEnds.size(); ++i)
        longestPass = std::max(longestPass, passEnds[i] - passEnds[i - 1]);
    INFO("rendered " << result.seconds << " s in " << result.passes << " passes, longest "
                     << longestPass << " s, " << result.samplesPerPixel << " spp");
    CHECK(passEnds.back() <= options.timeBudget + longestPass);
    CHECK(passEnds.back() >= options.timeBudget - longestPass);
    CHECK(result.samplesTaken == result.samplesPerPixel * 40 * 30);
}

namespace {

/// The start of an AOV test's scene: `integrator` recording `aovs`, `spp` samples of
/// `sampler`, and a width × height camera at the origin looking down −z (40° field of
/// view, box filter); the test adds its content and the closing </scene>.
std::string aovTestScene(const std::string &integrator, const std::string &aovs,
                         const std::string &sampler, int spp, int width, int height) {
    return fmt::format(R"(<scene>
        <integrator type="{}"><string name="aovs" value="{}"/></integrator>
        <sampler type="{}"><integer name="sampleCount" value="{}"/></sampler>
        <camera type="perspective"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <float name="fov" value="40"/><rfilter type="box"/>
            <transform name="toWorld"><lookat origin="0,0,0" target="0,0,-1"/></transform></camera>
)",
                       integrator, aovs, sampler, spp, width, height);
}

} // namespace

TEST_CASE("AOVs: the albedo, normal, depth and position of a plane", "[render][aov]") {
    // A diffuse plane z = −2 facing the camera at the origin, tilted about x by 30°.
    const Vector3f normal(0.0f, std::sin(degToRad(30.0f)), std::cos(degToRad(30.0f)));
    const Point3f onPlane(0.0f, 0.0f, -2.0f);
    TempDir dir;
    dir.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    auto scene = loadScene(
        aovTestScene("direct_mis", "albedo, normal depth,position", "sobol", 16, 24, 16) + R"(
        <mesh type="obj"><string name="filename" value="quad.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="0.2, 0.4, 0.6"/></bsdf>
            <transform name="toWorld"><scale value="10"/><rotate axis="1,0,0" angle="-30"/>
                <translate value="0,0,-2"/></transform></mesh>
        <emitter type="point"><point name="position" value="0,0,0"/><color name="power" value="10"/></emitter>
    </scene>)",
        dir.path().string());
    const RenderResult result = renderScene(*scene, quietOptions(2));
    const Bitmap albedo = result.layers.layer("albedo"), normals = result.layers.layer("normal"),
                 depth = result.layers.layer("depth"), position = result.layers.layer("position");
    const Camera &camera = *scene->getCamera();
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            CAPTURE(x, y);
            CHECK(albedo(y, x).isApprox(Color3f(0.2f, 0.4f, 0.6f), 1e-5f));
            CHECK(Vector3f(normals(y, x).matrix()).isApprox(normal, 1e-5f));
            // The position is a mean of points on the plane: on the plane.
            const Point3f p(position(y, x).matrix());
            CHECK(std::abs((p - onPlane).dot(normal)) < 1e-4f);
            // The depth: the distance along each camera ray, averaged over a fine grid of
            // the pixel (it varies smoothly, so 16 Sobol' samples match it to ~0.1%).
            double expected = 0.0;
            for (int s = 0; s < 64; ++s) {
                const int row = s / 8, column = s % 8;
                Ray3f ray;
                camera.sampleRay(ray, Point2f(x + (column + 0.5f) / 8, y + (row + 0.5f) / 8),
                                 Point2f(0.5f, 0.5f));
                expected += (onPlane - ray.o).dot(normal) / ray.d.dot(normal) / 64.0;
            }
            CHECK(depth(y, x).r() == Approx(expected).epsilon(2e-3));
            CHECK(depth(y, x).r() == depth(y, x).b()); // a single channel, shown as grey
        }
    CHECK(result.layers.channelsOf("depth") == std::vector<std::string>{"Z"});
    CHECK(result.layers.channelsOf("normal") == std::vector<std::string>{"X", "Y", "Z"});
}

TEST_CASE("AOVs: behind smooth glass, the albedo of what it refracts", "[render][aov]") {
    // A glass ball fills the middle of the view of a diffuse plane: near its centre every
    // camera ray refracts far more likely than it reflects (F ≈ 4 %), so the albedo there is
    // the plane's, exactly, and not a mix with the black that the reflections see.
    TempDir dir;
    dir.write("quad.obj", "v -10 -10 0\nv 10 -10 0\nv 10 10 0\nv -10 10 0\nf 1 2 3 4\n");
    auto scene = loadScene(aovTestScene("path_mis", "albedo", "independent", 64, 16, 16) + R"(
        <mesh type="sphere"><point name="center" value="0,0,-2"/><float name="radius" value="0.5"/>
            <bsdf type="dielectric"/></mesh>
        <mesh type="obj"><string name="filename" value="quad.obj"/>
            <transform name="toWorld"><translate value="0,0,-4"/></transform>
            <bsdf type="diffuse"><color name="albedo" value="0.2, 0.4, 0.6"/></bsdf></mesh>
        <emitter type="point"><point name="position" value="0,0,0"/><color name="power" value="10"/></emitter>
    </scene>)",
                           dir.path().string());
    const Bitmap albedo = renderScene(*scene, quietOptions(2)).layers.layer("albedo");
    for (int y = 6; y < 10; ++y)
        for (int x = 6; x < 10; ++x) {
            CAPTURE(x, y);
            CHECK(albedo(y, x).isApprox(Color3f(0.2f, 0.4f, 0.6f), 1e-5f));
        }
}

TEST_CASE("AOVs: emission is the light a camera ray meets first", "[render][aov]") {
    // Seen from the origin along −z, with a box filter: the left half of the image is an
    // area light of radiance (1, 2, 3) facing the camera, the lower right quarter a
    // diffuse plane, the upper right quarter the constant
    // environment of 0.25. The column and row boundaries fall between pixels.
    TempDir dir;
    dir.write("left.obj", "v -10 -10 0\nv 0 -10 0\nv 0 10 0\nv -10 10 0\nf 1 2 3 4\n");
    dir.write("lowerRight.obj", "v 0 -10 0\nv 10 -10 0\nv 10 0 0\nv 0 0 0\nf 1 2 3 4\n");
    auto scene = loadScene(aovTestScene("path_mis", "emission", "independent", 4, 24, 16) + R"(
        <mesh type="obj"><string name="filename" value="left.obj"/>
            <transform name="toWorld"><translate value="0,0,-2"/></transform>
            <emitter type="area"><color name="radiance" value="1, 2, 3"/></emitter></mesh>
        <mesh type="obj"><string name="filename" value="lowerRight.obj"/>
            <transform name="toWorld"><translate value="0,0,-2"/></transform>
            <bsdf type="diffuse"/></mesh>
        <emitter type="constant"><color name="radiance" value="0.25"/></emitter>
    </scene>)",
                           dir.path().string());
    const RenderResult result = renderScene(*scene, quietOptions(2));
    const Bitmap emission = result.layers.layer("emission");
    CHECK(result.layers.channelsOf("emission") == std::vector<std::string>{"R", "G", "B"});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x) {
            CAPTURE(x, y);
            const Color3f expected = x < 12  ? Color3f(1.0f, 2.0f, 3.0f)
                                     : y < 8 ? Color3f(0.25f)
                                             : Color3f(0.0f);
            CHECK(emission(y, x).isApprox(expected, 1e-6f));
        }
}

TEST_CASE("The variance AOV estimates the variance of each pixel's mean", "[render][aov]") {
    // Eight renders with different seeds: the spread of each pixel across them against
    // the mean of the variance layer, over the image (box filter: pixels independent).
    constexpr int kRenders = 8;
    std::vector<Bitmap> images;
    double layerMean = 0.0;
    for (int seed = 0; seed < kRenders; ++seed) {
        RenderOptions options = quietOptions(2);
        options.aovs = {AOV::Variance, AOV::SampleCount};
        const RenderResult result =
            renderScene(*loadScene(aoScene("independent", 16, "box", seed)), options);
        images.push_back(result.image);
        const Bitmap variance = result.layers.layer("variance");
        const Bitmap counts = result.layers.layer("sampleCount");
        for (int y = 0; y < 30; ++y)
            for (int x = 0; x < 40; ++x) {
                layerMean += variance(y, x).r() / (kRenders * 1200.0);
                CHECK(counts(y, x).r() == 16.0f);
            }
    }
    double spread = 0.0; // the mean over pixels of the unbiased variance across renders
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            RunningMoments moments;
            for (const Bitmap &image : images)
                moments.add(image(y, x).r());
            spread += moments.variance() / 1200.0;
        }
    // Both are means of 1200 × 8 and 1200 × 7 degrees of freedom of noisy estimates of
    // the same quantity: within 10% (each has a relative error of about 2%).
    INFO("variance layer " << layerMean << ", spread across seeds " << spread);
    CHECK(layerMean == Approx(spread).epsilon(0.1));
    // Control: a factor of 2 (the variance of one half-buffer's mean instead of the
    // whole's, (A − B)²/2) is outside the tolerance.
    CHECK_FALSE(2.0 * layerMean == Approx(spread).epsilon(0.1));
    CHECK(spread > 1e-3); // the scene is noisy: not 0 ≈ 0
}

TEST_CASE("Adaptive sampling spends samples where the noise is", "[render][adaptive]") {
    auto scene = loadScene(aoScene("independent", 1024, "box", 0,
                                   R"(<float name="maxTolerance" value="0.1"/>
                                      <integer name="minSamples" value="32"/>)"));
    RenderOptions options = quietOptions(2);
    options.aovs = {AOV::SampleCount};
    const RenderResult result = renderScene(*scene, options);
    const Bitmap counts = result.layers.layer("sampleCount");
    float fewest = 1e9f, most = 0.0f;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) {
            fewest = std::min(fewest, counts(y, x).r());
            most = std::max(most, counts(y, x).r());
        }
    CHECK(result.complete);
    CHECK(result.convergedPixels > 0);
    // The sky (AO 0, no variance) stops at the first check after minSamples (a pass ends
    // at 32 spp); occluded corners need far more.
    CHECK(fewest == 32.0f);
    CHECK(most > 256.0f);
    CHECK(result.samplesTaken < 1024u * 1200u / 2);
}

TEST_CASE("Adaptive sampling leaves the image unbiased", "[render][adaptive][ttest]") {
    // A floor lit by a sphere light that only BSDF sampling finds (path_mats): one sample
    // in 16 sees it, so many pixels see no light in their first 16 samples. Stopped on
    // those samples (mean 0, variance 0) they stayed black; stopped on the separate
    // decision samples, the image samples' mean is unbiased. Sixteen renders of 32×32
    // pixels each way (seeds apart), their image means compared by Welch's t-test at 1 %.
    auto render = [](int seed, const std::string &samplerExtra, int spp) {
        auto scene = loadScene(fmt::format(R"(<scene>
            <integrator type="path_mats"/>
            <sampler type="independent"><integer name="sampleCount" value="{}"/>
                <integer name="seed" value="{}"/>{}</sampler>
            <camera type="perspective"><float name="fov" value="40"/>
                <integer name="width" value="32"/><integer name="height" value="32"/>
                <transform name="toWorld"><lookat origin="0,3,3" target="0,0,0"/></transform>
                <rfilter type="box"/>
            </camera>
            <mesh type="sphere"><point name="center" value="0,-1000,0"/><float name="radius" value="1000"/></mesh>
            <mesh type="sphere"><point name="center" value="0,2,0"/><float name="radius" value="0.5"/>
                <emitter type="area"><color name="radiance" value="10"/></emitter></mesh>
        </scene>)",
                                           spp, seed, samplerExtra));
        RenderOptions options = quietOptions(2);
        options.aovs = {AOV::SampleCount};
        return renderScene(*scene, options);
    };
    auto imageMean = [](const Bitmap &image) {
        double sum = 0.0;
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x)
                sum += image(y, x).getLuminance();
        return sum / double(image.width() * image.height());
    };
    RunningMoments adaptive, plain;
    double fewest = 1e9, most = 0.0;
    for (int seed = 0; seed < 16; ++seed) {
        const RenderResult result = render(seed, R"(<float name="maxTolerance" value="0.1"/>
            <integer name="minSamples" value="16"/>)",
                                           1024);
        adaptive.add(imageMean(result.image));
        const Bitmap counts = result.layers.layer("sampleCount");
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                fewest = std::min(fewest, double(counts(y, x).r()));
                most = std::max(most, double(counts(y, x).r()));
            }
        plain.add(imageMean(render(100 + seed, "", 64).image));
    }
    const double standardError =
        std::sqrt(adaptive.variance() / adaptive.count + plain.variance() / plain.count);
    const double t = (adaptive.mean - plain.mean) / standardError;
    INFO("adaptive " << adaptive.mean << ", plain " << plain.mean << ", standard error "
                     << standardError << ", t = " << t << "; samples per pixel " << fewest << " to "
                     << most);
    CHECK(2.0 * (1.0 - studentTCdf(std::abs(t), 15.0)) > 0.01);
    // It adapts: some pixels stop at minSamples, others run on.
    CHECK(fewest == 16.0);
    CHECK(most > 64.0);
    // Negative control: a reference 3 % brighter is told apart.
    const double tControl = (adaptive.mean - 1.03 * plain.mean) / standardError;
    CHECK(2.0 * (1.0 - studentTCdf(std::abs(tControl), 15.0)) < 0.01);
}

TEST_CASE("Multi-layer EXR and PFM files round-trip", "[image][aov]") {
    TempDir dir;
    Bitmap colour(Vector2i(5, 3));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            colour(y, x) = Color3f(0.1f * x, -2.5f * y, 1e6f * (x + y));
    LayeredImage image;
    image.addLayer("", {"R", "G", "B"}, colour);
    image.addLayer("albedo", {"R", "G", "B"}, colour);
    image.addLayer("depth", {"Z"}, colour);
    image.attributes["nori/scene"] = "cbox.xml";
    const std::string exr = (dir.path() / "layers.exr").string();
    image.saveEXR(exr);
    const LayeredImage read = LayeredImage::loadEXR(exr);
    CHECK(read.layerNames() == std::vector<std::string>{"", "albedo", "depth"});
    CHECK(identicalImages(read.layer(""), colour));
    CHECK(identicalImages(read.layer("albedo"), colour));
    CHECK((read.layer("depth")(2, 4) == Color3f(colour(2, 4).r())).all());
    CHECK(read.attributes.at("nori/scene") == "cbox.xml");
    // A texture load takes the beauty's R, G, B.
    CHECK(identicalImages(Bitmap::load(exr), colour));
    CHECK_THAT(nori::testing::errorOf([&] { read.layer("normal"); }),
               Contains("no layer 'normal' (its layers: (beauty), albedo, depth)"));

    const std::string pfm = (dir.path() / "image.pfm").string();
    colour.savePFM(pfm);
    CHECK(identicalImages(Bitmap::load(pfm), colour));
    // Truncated or malformed PFM files are errors naming the file.
    const std::string bytes = readBinaryFile(pfm, "test");
    CHECK_THAT(nori::testing::errorOf(
                   [&] { decodeImageFile(bytes.substr(0, bytes.size() - 1), "short.pfm"); }),
               Contains("'short.pfm' ends early"));
    CHECK_THAT(nori::testing::errorOf([&] { decodeImageFile("PF\n5 x3\n-1\n", "bad.pfm"); }),
               Contains("'bad.pfm' has a malformed header"));
}

TEST_CASE("nori --aovs and --pfm write the layers and OIDN's inputs", "[cli][aov]") {
    TempDir dir;
    dir.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    const std::string scene = dir.write("plane.xml", R"(<scene><integrator type="ao"/>
        <camera type="perspective"><integer name="width" value="8"/><integer name="height" value="8"/>
            <transform name="toWorld"><lookat origin="0,0,3" target="0,0,0"/></transform></camera>
        <mesh type="obj"><string name="filename" value="quad.obj"/></mesh></scene>)");
    auto result = nori::testing::runNori(
        {"--aovs", "depth,sampleCount", "--pfm", "--no-progress", "--spp", "4", scene});
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    const LayeredImage image = LayeredImage::loadEXR((dir.path() / "plane.exr").string());
    CHECK(image.layerNames() ==
          std::vector<std::string>{"", "albedo", "depth", "normal", "sampleCount"});
    CHECK(image.layer("sampleCount")(4, 4).r() == 4.0f);
    CHECK(image.layer("depth")(4, 4).r() == Approx(3.0f).epsilon(0.01));
    for (const char *file : {"plane.pfm", "plane_albedo.pfm", "plane_normal.pfm"})
        CHECK(std::filesystem::exists(dir.path() / file));
    CHECK(Bitmap::load((dir.path() / "plane_normal.pfm").string())(4, 4).isApprox(
        Color3f(0.0f, 0.0f, 1.0f), 1e-5f));

    auto typo = nori::testing::runNori({"--aovs", "albdo", scene});
    CHECK(typo.exitCode == 1);
    CHECK_THAT(typo.output, Contains("--aovs: unknown AOV 'albdo' (did you mean 'albedo'?)"));
}

TEST_CASE("Filter importance sampling draws offsets in proportion to |filter|",
          "[render][adaptive][chi2]") {
    for (const std::string type : {"gaussian", "mitchell", "tent", "box"}) {
        CAPTURE(type);
        auto filter = std::dynamic_pointer_cast<ReconstructionFilter>(
            loadFromXMLString(fmt::format(R"(<rfilter type="{}"/>)", type)));
        REQUIRE(filter);
        const FilterSampler sampler(filter.get());
        const float radius = filter->getRadius();
        // 64 bins over [−r, r]; expected counts ∝ ∫|f| over each bin (midpoint rule on
        // a fine grid), and the sign of f where the sample lands.
        constexpr int kBins = 64, kSamples = 200000;
        std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0), control(kBins, 1.0);
        PCG32 random(7, 3);
        size_t wrongSign = 0;
        for (int i = 0; i < kSamples; ++i) {
            float sign;
            const float u = random.nextFloat();
            const Point2f offset = sampler.sample(Point2f(u, random.nextFloat()), sign);
            const int bin = std::clamp(
                static_cast<int>((offset.x() + radius) / (2 * radius) * kBins), 0, kBins - 1);
            observed[static_cast<size_t>(bin)] += 1.0;
            const float f = filter->eval(offset.x()) * filter->eval(offset.y());
            wrongSign += (f < -1e-4f && sign > 0.0f) || (f > 1e-4f && sign < 0.0f) ? 1 : 0;
        }
        double total = 0.0;
        for (int bin = 0; bin < kBins; ++bin) {
            for (int k = 0; k < 100; ++k) {
                const float x = -radius + 2 * radius * (bin + (k + 0.5f) / 100) / kBins;
                // The tabulated filter, as ImageBlock and FilterSampler use it.
                const float step = radius / 32;
                expected[static_cast<size_t>(bin)] +=
                    std::abs(filter->eval(std::floor(std::abs(x) / step) * step));
            }
            total += expected[static_cast<size_t>(bin)];
        }
        for (double &count : expected)
            count *= kSamples / total;
        for (double &count : control)
            count = double(kSamples) / kBins;
        const ChiSquareResult result = pearsonChiSquareTest(observed, expected, 5.0, 0.01);
        INFO(result.message);
        CHECK(result.passed);
        CHECK(wrongSign < kSamples / 1000); // only at the steps' edges
        if (type != "box") // Control: a uniform density is rejected for a peaked filter.
            CHECK_FALSE(pearsonChiSquareTest(observed, control, 5.0, 0.01).passed);
    }
}

TEST_CASE("Filter importance sampling at the image's edge draws from the cut filter",
          "[render][adaptive][chi2]") {
    // A pixel whose filter reaches past the image's edge samples offsets in
    // [lower, upper] only, in proportion to |f| there: what splatting reconstructs an
    // edge pixel from (the samples inside the image).
    for (const std::string type : {"gaussian", "mitchell"}) {
        CAPTURE(type);
        auto filter = std::dynamic_pointer_cast<ReconstructionFilter>(
            loadFromXMLString(fmt::format(R"(<rfilter type="{}"/>)", type)));
        REQUIRE(filter);
        const FilterSampler sampler(filter.get());
        const float radius = filter->getRadius(), lower = -0.5f, upper = radius;
        constexpr int kBins = 48, kSamples = 200000;
        std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0), uncut(kBins, 0.0);
        PCG32 random(11, 5);
        size_t outside = 0;
        for (int i = 0; i < kSamples; ++i) {
            float sign;
            const float u = random.nextFloat();
            const Point2f offset =
                sampler.sample(Point2f(u, random.nextFloat()), sign, Vector2f(lower, -radius),
                               Vector2f(upper, radius));
            outside += offset.x() < lower || offset.x() > upper ? 1 : 0;
            const int bin = std::clamp(
                static_cast<int>((offset.x() - lower) / (upper - lower) * kBins), 0, kBins - 1);
            observed[static_cast<size_t>(bin)] += 1.0;
        }
        // Expected: the tabulated |f| over [lower, upper]; the control: |f| over [−r, r]
        // folded into the same bins by clamping (what an uncut sampler would give).
        double total = 0.0;
        const float step = radius / 32;
        for (int bin = 0; bin < kBins; ++bin) {
            for (int k = 0; k < 100; ++k) {
                const float x = lower + (upper - lower) * (bin + (k + 0.5f) / 100) / kBins;
                expected[static_cast<size_t>(bin)] +=
                    std::abs(filter->eval(std::floor(std::abs(x) / step) * step));
            }
            total += expected[static_cast<size_t>(bin)];
        }
        for (double &count : expected)
            count *= kSamples / total;
        double uncutTotal = 0.0;
        for (int k = 0; k < 100 * kBins; ++k) {
            const float x = -radius + 2 * radius * (k + 0.5f) / (100 * kBins);
            const double weight = std::abs(filter->eval(std::floor(std::abs(x) / step) * step));
            const int bin =
                std::clamp(static_cast<int>((x - lower) / (upper - lower) * kBins), 0, kBins - 1);
            uncut[static_cast<size_t>(bin)] += weight;
            uncutTotal += weight;
        }
        for (double &count : uncut)
            count *= kSamples / uncutTotal;
        const ChiSquareResult result = pearsonChiSquareTest(observed, expected, 5.0, 0.01);
        INFO(result.message);
        CHECK(result.passed);
        CHECK(outside == 0);
        CHECK_FALSE(pearsonChiSquareTest(observed, uncut, 5.0, 0.01).passed);
    }
}

TEST_CASE("Filter importance sampling converges to the splatted image", "[render][adaptive]") {
    // Per-pixel differences of the two reconstructions at 64 spp have mean zero (t-test
    // over the pixels), for a positive filter and for one with negative lobes.
    for (const std::string filter : {"gaussian", "mitchell"}) {
        CAPTURE(filter);
        auto scene = loadScene(aoScene("sobol", 64, filter));
        RenderOptions options = quietOptions(2);
        const RenderResult splatted = renderScene(*scene, options);
        options.filterImportanceSampling = true;
        const RenderResult sampled = renderScene(*scene, options);
        auto differenceTest = [&](float scale) {
            RunningMoments differences;
            for (int y = 0; y < 30; ++y)
                for (int x = 0; x < 40; ++x)
                    differences.add(scale * sampled.image(y, x).r() - splatted.image(y, x).r());
            return studentTTest(differences.mean, differences.variance(), differences.count, 0.0,
                                0.01);
        };
        const StudentTResult same = differenceTest(1.0f);
        INFO("t = " << same.t);
        CHECK(same.passed);
        CHECK_FALSE(differenceTest(1.03f).passed); // control: 3% off is seen
    }
}
