// Textures: the MIP pyramid and its filters against independent computations, wrap
// modes, sRGB decoding, the checkerboards, binding by name and the errors of bad
// parameters.
#include "testutil.h"

#include <nori/bsdf.h>
#include <nori/mipmap.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/texturecache.h>

#include <catch2/catch.hpp>
#include <stb_image_write.h>

#include <cstring>
#include <thread>

using namespace nori;
using namespace nori::testing;
using Catch::Matchers::Contains;

namespace {

Bitmap randomImage(int width, int height, uint64_t seed) {
    PCG32 rng(seed, 1);
    Bitmap image(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image(y, x) = Color3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
    return image;
}

/// The mean of the piecewise-constant image over the rectangle [x0, x1) × [y0, y1) (in
/// texels), by exact overlap areas: the definition of a box filter.
Color3f boxAverage(const Bitmap &image, double x0, double x1, double y0, double y1) {
    Color3f sum(0.0f);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            const double ox = std::max(0.0, std::min(x1, x + 1.0) - std::max(x0, double(x)));
            const double oy = std::max(0.0, std::min(y1, y + 1.0) - std::max(y0, double(y)));
            sum += float(ox * oy) * image(y, x);
        }
    return sum / float((x1 - x0) * (y1 - y0));
}

/// Whether two images have the same size and the same bits in every texel.
bool sameBits(const Bitmap &a, const Bitmap &b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.data(), b.data(), sizeof(Color3f) * static_cast<size_t>(a.size())) == 0;
}

std::shared_ptr<Texture> loadTexture(const std::string &xml, const std::string &directory = ".") {
    auto texture = std::dynamic_pointer_cast<Texture>(loadFromXMLString(xml, directory));
    REQUIRE(texture);
    return texture;
}

} // namespace

TEST_CASE("Each pyramid level is the box average of the one below", "[texture][mipmap]") {
    for (auto [width, height] : {std::pair{32, 16}, std::pair{37, 20}, std::pair{5, 1}}) {
        CAPTURE(width, height);
        const MIPMap mipmap(randomImage(width, height, 7));
        REQUIRE(mipmap.level(mipmap.levels() - 1).size() == 1);
        for (int level = 1; level < mipmap.levels(); ++level) {
            const Bitmap &below = mipmap.level(level - 1), &here = mipmap.level(level);
            CHECK(here.width() == std::max(1, below.width() / 2));
            CHECK(here.height() == std::max(1, below.height() / 2));
            const double sx = double(below.width()) / here.width();
            const double sy = double(below.height()) / here.height();
            for (int y = 0; y < here.height(); ++y)
                for (int x = 0; x < here.width(); ++x) {
                    const Color3f expected =
                        boxAverage(below, x * sx, (x + 1) * sx, y * sy, (y + 1) * sy);
                    for (int c = 0; c < 3; ++c)
                        CHECK(here(y, x)[c] == Approx(expected[c]).margin(1e-5));
                }
        }
        // The box filter keeps the mean: the 1×1 level is the image's average.
        for (int c = 0; c < 3; ++c)
            CHECK(mipmap.level(mipmap.levels() - 1)(0, 0)[c] ==
                  Approx(mipmap.average()[c]).margin(1e-5));
    }
    // Power-of-two sizes: plainly the mean of 2×2 texels.
    const MIPMap square(randomImage(8, 8, 3));
    CHECK(square.level(1)(1, 2).isApprox(0.25f * (square.level(0)(2, 4) + square.level(0)(2, 5) +
                                                  square.level(0)(3, 4) + square.level(0)(3, 5)),
                                         1e-6f));
}

TEST_CASE("The levels above 0 are built on first use, once, whichever threads ask",
          "[texture][mipmap]") {
    const Bitmap image = randomImage(37, 20, 5);
    // The reference: the chain of downsamplings, built here eagerly.
    std::vector<Bitmap> expected{image};
    while (expected.back().width() > 1 || expected.back().height() > 1)
        expected.push_back(MIPMap::downsample(expected.back()));

    const MIPMap mipmap(image);
    REQUIRE(mipmap.levels() == static_cast<int>(expected.size())); // 37 → 18 → 9 → 4 → 2 → 1
    // Lookups on level 0 (nearest, bilinear, a trilinear one whose footprint is below a
    // texel) do not build the others.
    const Point2f st(0.3f, 0.6f);
    mipmap.nearest(st, MIPMap::Wrap::Repeat);
    mipmap.bilinear(0, st, MIPMap::Wrap::Repeat);
    mipmap.trilinear(st, Vector2f(1e-4f, 0.0f), Vector2f(0.0f, 1e-4f), MIPMap::Wrap::Repeat);
    CHECK(sameBits(mipmap.level(0), image));
    CHECK_FALSE(mipmap.pyramidBuilt());

    // Threads asking at once for levels above 0 all see the same, complete levels.
    constexpr int kThreads = 4;
    std::vector<std::vector<Color3f>> seen(kThreads);
    std::vector<std::thread> threads;
    for (int thread = 0; thread < kThreads; ++thread)
        threads.emplace_back([&, thread] {
            for (int level = mipmap.levels() - 1 - thread % 2; level >= 1; --level) {
                const Bitmap &here = mipmap.level(level);
                seen[thread].push_back(here(here.height() - 1, here.width() - 1));
                seen[thread].push_back(mipmap.bilinear(level, st, MIPMap::Wrap::Clamp));
            }
        });
    for (std::thread &thread : threads)
        thread.join();
    CHECK(mipmap.pyramidBuilt());
    for (int level = 1; level < mipmap.levels(); ++level) {
        CAPTURE(level);
        CHECK(sameBits(mipmap.level(level), expected[level]));
    }
    for (int thread = 0; thread < kThreads; ++thread) {
        int k = 0;
        for (int level = mipmap.levels() - 1 - thread % 2; level >= 1; --level) {
            const Bitmap &here = expected[level];
            CHECK((seen[thread][k++] == here(here.height() - 1, here.width() - 1)).all());
            CHECK((seen[thread][k++] == mipmap.bilinear(level, st, MIPMap::Wrap::Clamp)).all());
        }
    }

    // A 1×1 image has no level to build.
    const MIPMap single(randomImage(1, 1, 2));
    CHECK(single.levels() == 1);
    CHECK(single.pyramidBuilt());
}

TEST_CASE("Wrap modes repeat, clamp and mirror texel indices", "[texture][mipmap]") {
    const MIPMap mipmap(randomImage(4, 3, 11));
    const Bitmap &image = mipmap.level(0);
    using W = MIPMap::Wrap;
    CHECK(mipmap.texel(0, -1, 0, W::Repeat).isApprox(image(0, 3)));
    CHECK(mipmap.texel(0, 5, -1, W::Repeat).isApprox(image(2, 1)));
    CHECK(mipmap.texel(0, -1, 7, W::Clamp).isApprox(image(2, 0)));
    CHECK(mipmap.texel(0, 9, 1, W::Clamp).isApprox(image(1, 3)));
    // Mirror: … 1 0 | 0 1 2 3 | 3 2 …
    CHECK(mipmap.texel(0, -1, 0, W::Mirror).isApprox(image(0, 0)));
    CHECK(mipmap.texel(0, -2, 0, W::Mirror).isApprox(image(0, 1)));
    CHECK(mipmap.texel(0, 4, 0, W::Mirror).isApprox(image(0, 3)));
    CHECK(mipmap.texel(0, 6, 3, W::Mirror).isApprox(image(2, 1)));
    // Lookups far outside [0, 1]² stay exact for repeat (a whole number of periods).
    const Point2f st(0.375f, 0.5f);
    CHECK(mipmap.nearest(st + Point2f(1000.0f, -3.0f), W::Repeat)
              .isApprox(mipmap.nearest(st, W::Repeat)));
    CHECK(mipmap.bilinear(0, Point2f(-0.4f, 0.5f), W::Clamp)
              .isApprox(mipmap.bilinear(0, Point2f(0.0f, 0.5f), W::Clamp)));
}

TEST_CASE("8-bit images decode from sRGB: 128 becomes 0.21586", "[texture]") {
    TempDir dir;
    const unsigned char grey[3] = {128, 128, 128};
    const std::string file = (dir.path() / "grey.png").string();
    REQUIRE(stbi_write_png(file.c_str(), 1, 1, 3, grey, 3));
    const auto srgb = loadTextureImage(file, ColorSpace::Auto);
    CHECK(srgb->level(0)(0, 0).r() == Approx(0.21586f).epsilon(1e-4));
    const auto linear = loadTextureImage(file, ColorSpace::Linear);
    CHECK(linear->level(0)(0, 0).r() == Approx(128.0f / 255.0f).epsilon(1e-6));
    // The same file and colour space share one pyramid.
    CHECK(loadTextureImage(file, ColorSpace::Auto) == srgb);
    // A float image is linear by default: a texture reads back what was saved.
    Bitmap value(Eigen::Vector2i(1, 1));
    value(0, 0) = Color3f(0.21586f, 2.5f, 0.0f);
    value.saveEXR((dir.path() / "value.exr").string());
    auto texture = loadTexture(R"(<texture type="image"><string name="filename" value="value.exr"/>
        <string name="filter" value="nearest"/></texture>)",
                               dir.path().string());
    CHECK(texture->eval(TextureQuery(Point2f(0.5f, 0.5f))).isApprox(value(0, 0)));
    // A power law: 128/255 to the 2.2, and gamma -1 is sRGB (Mitsuba's spelling).
    const auto gamma = loadTextureImage(file, ColorSpace::Gamma, 2.2f);
    CHECK(gamma->level(0)(0, 0).r() == Approx(std::pow(128.0f / 255.0f, 2.2f)).epsilon(1e-5));
    CHECK(loadTextureImage(file, ColorSpace::Gamma, 1.8f) != gamma);
    auto byGamma = [&](const std::string &parameters) {
        return loadTexture(R"(<texture type="image"><string name="filename" value="grey.png"/>
            <string name="filter" value="nearest"/>)" +
                               parameters + "</texture>",
                           dir.path().string())
            ->eval(TextureQuery(Point2f(0.5f, 0.5f)))
            .r();
    };
    CHECK(byGamma(R"(<float name="gamma" value="2.2"/>)") ==
          Approx(std::pow(128.0f / 255.0f, 2.2f)).epsilon(1e-5));
    CHECK(byGamma(R"(<float name="gamma" value="-1"/>)") == Approx(0.21586f).epsilon(1e-4));
    CHECK_THAT(errorOf([&] { byGamma(R"(<float name="gamma" value="0"/>)"); }),
               Catch::Contains("'gamma' must lie in (0, 16]"));
    CHECK_THAT(
        errorOf([&] {
            byGamma(R"(<float name="gamma" value="2"/><string name="colorSpace" value="srgb"/>)");
        }),
        Catch::Contains("give 'colorSpace' or 'gamma', not both"));
}

TEST_CASE("Trilinear filtering mixes the two levels around the footprint", "[texture][mipmap]") {
    const MIPMap mipmap(randomImage(64, 64, 5));
    const Point2f st(0.3f, 0.6f);
    // width = 2·max|∂st| = 2^1.3/64 gives level 1.3: 0.7 of level 1 and 0.3 of level 2.
    const float derivative = std::exp2(1.3f) / 64.0f / 2.0f;
    const Vector2f dst0(derivative, 0.0f), dst1(0.0f, 0.5f * derivative);
    CHECK(mipmap.trilinearLevel(dst0, dst1) == Approx(1.3f).epsilon(1e-5));
    const Color3f expected = 0.7f * mipmap.bilinear(1, st, MIPMap::Wrap::Repeat) +
                             0.3f * mipmap.bilinear(2, st, MIPMap::Wrap::Repeat);
    CHECK(mipmap.trilinear(st, dst0, dst1, MIPMap::Wrap::Repeat).isApprox(expected, 1e-5f));
    // A point footprint uses level 0; a huge one the 1×1 level, the image's mean.
    CHECK(mipmap.trilinear(st, Vector2f::Zero(), Vector2f::Zero(), MIPMap::Wrap::Repeat)
              .isApprox(mipmap.bilinear(0, st, MIPMap::Wrap::Repeat)));
    CHECK(mipmap.trilinear(st, Vector2f(5.0f, 0.0f), Vector2f(0.0f, 5.0f), MIPMap::Wrap::Repeat)
              .isApprox(mipmap.level(mipmap.levels() - 1)(0, 0), 1e-5f));
}

TEST_CASE("EWA on an axis-aligned footprint is the Gaussian-weighted texel sum",
          "[texture][mipmap]") {
    const MIPMap mipmap(randomImage(64, 64, 9));
    const Point2f st(0.52f, 0.27f);
    for (int level : {0, 1, 2}) {
        CAPTURE(level);
        const int size = 64 >> level;
        // Semi-axes of 3 and 1.5 texels of this level, along s and t.
        const Vector2f dst0(3.0f / size, 0.0f), dst1(0.0f, 1.5f / size);
        // The ellipse grown by one texel: (s/a')² + (t/b')² < 1 with a'² = a² + 1 (Heckbert
        // 1989 §3.5.5), each texel weighted by exp(−2r²) − exp(−2).
        const double a2 = 9.0 + 1.0, b2 = 2.25 + 1.0;
        const double s = st.x() * size - 0.5, t = st.y() * size - 0.5;
        Color3f sum(0.0f);
        double weights = 0.0;
        for (int y = -10; y < size + 10; ++y)
            for (int x = -10; x < size + 10; ++x) {
                const double r2 = (x - s) * (x - s) / a2 + (y - t) * (y - t) / b2;
                if (r2 >= 1.0)
                    continue;
                const double weight = std::exp(-2.0 * r2) - std::exp(-2.0);
                sum += float(weight) * mipmap.texel(level, x, y, MIPMap::Wrap::Repeat);
                weights += weight;
            }
        const Color3f expected = sum / float(weights);
        CHECK(mipmap.ewaOnLevel(level, st, dst0, dst1, MIPMap::Wrap::Repeat)
                  .isApprox(expected, 1e-5f));
    }
    // The full filter picks the level of the minor axis: 1.5 texels of level 1 = 3 of level 0
    // → log2(3) = 1.585, between levels 1 and 2.
    const Vector2f major(6.0f / 64.0f, 0.0f), minor(0.0f, 3.0f / 64.0f);
    CHECK(mipmap.ewaLevel(major, minor, 8.0f) == Approx(std::log2(3.0f)).epsilon(1e-5));
    // Eccentricity beyond maxAnisotropy widens the minor axis: 64:1 clamped to 8:1.
    CHECK(mipmap.ewaLevel(Vector2f(64.0f / 64.0f, 0.0f), Vector2f(0.0f, 1.0f / 64.0f), 8.0f) ==
          Approx(3.0f).epsilon(1e-5));
}

TEST_CASE("The course's checkerboards follow i = floor(u/scale.x - delta.x)", "[texture]") {
    auto color = loadTexture(R"(<texture type="checkerboard_color">
        <point name="delta" value="0.5, 0.25"/> <vector name="scale" value="0.1, 0.2"/>
        <color name="value1" value="1, 0, 0"/> <color name="value2" value="0, 0, 1"/></texture>)");
    auto value = [&](float u, float v) { return color->eval(TextureQuery(Point2f(u, v))); };
    // u = 0.06: i = floor(0.6 − 0.5) = 0; v = 0.1: j = floor(0.5 − 0.25) = 0 → even.
    CHECK(value(0.06f, 0.1f).isApprox(Color3f(1, 0, 0)));
    // u = 0.16: i = 1 → odd.
    CHECK(value(0.16f, 0.1f).isApprox(Color3f(0, 0, 1)));
    // u = 0.04: i = floor(−0.1) = −1; v = 0.0: j = floor(−0.25) = −1 → i + j = −2, even.
    CHECK(value(0.04f, 0.0f).isApprox(Color3f(1, 0, 0)));
    CHECK(value(0.04f, 0.1f).isApprox(Color3f(0, 0, 1)));
    auto scalar = loadTexture(R"(<texture type="checkerboard_float">
        <float name="value1" value="0.1"/> <float name="value2" value="0.7"/></texture>)");
    CHECK(scalar->evalFloat(TextureQuery(Point2f(0.5f, 0.5f))) == Approx(0.1f));
    CHECK(scalar->evalFloat(TextureQuery(Point2f(1.5f, 0.5f))) == Approx(0.7f));
    CHECK(scalar->average().x() == Approx(0.4f));
}

TEST_CASE("The filtered checkerboard is exact for points and fades to its mean", "[texture]") {
    auto checker = loadTexture(R"(<texture type="checkerboard"><float name="scale" value="4"/>
        <color name="color0" value="1"/> <color name="color1" value="0"/></texture>)");
    TextureQuery q(Point2f(0.1f, 0.1f));
    CHECK(checker->eval(q).x() == Approx(1.0f));
    q.uv = Point2f(0.3f, 0.1f);
    CHECK(checker->eval(q).x() == Approx(0.0f));
    // A footprint of many cells: the mean.
    q.dudx = q.dvdy = 10.0f;
    CHECK(checker->eval(q).x() == Approx(0.5f));
    // A footprint straddling one vertical edge symmetrically (u = 0.25 ± 0.05): half each.
    q = TextureQuery(Point2f(0.25f, 0.1f));
    q.dudx = 0.05f;
    CHECK(checker->eval(q).x() == Approx(0.5f).margin(1e-5));
}

TEST_CASE("Textures bind to parameters by name, misspelled or misplaced ones are errors",
          "[texture][parser]") {
    auto bsdf = std::dynamic_pointer_cast<BSDF>(loadFromXMLString(R"(<bsdf type="diffuse">
        <texture type="checkerboard" name="albedo"><color name="color0" value="0.8"/>
            <color name="color1" value="0.2"/></texture></bsdf>)"));
    REQUIRE(bsdf);
    BSDFQueryRecord bRec(Vector3f(0, 0, 1), Vector3f(0, 0, 1), ESolidAngle);
    bRec.uv = Point2f(0.1f, 0.1f);
    CHECK(bsdf->eval(bRec).x() == Approx(0.8f * kInvPi));
    bRec.uv = Point2f(0.6f, 0.1f);
    CHECK(bsdf->eval(bRec).x() == Approx(0.2f * kInvPi));
    // A <float> is accepted for a colour, as a grey.
    auto grey = std::dynamic_pointer_cast<BSDF>(
        loadFromXMLString(R"(<bsdf type="diffuse"><float name="albedo" value="0.25"/></bsdf>)"));
    CHECK(grey->eval(bRec).x() == Approx(0.25f * kInvPi));

    CHECK_THAT(errorOf([] {
                   loadFromXMLString(R"(<bsdf type="diffuse"><texture type="constant" name="albdo">
                       <color name="value" value="0.5"/></texture></bsdf>)");
               }),
               Contains("albdo") && Contains("albedo"));
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(
                       R"(<bsdf type="dielectric"><texture type="constant" name="intIOR">
                       <color name="value" value="1.5"/></texture></bsdf>)");
               }),
               Contains("'intIOR' is a nested object, but a float was expected"));
    CHECK_THAT(
        errorOf([] {
            loadFromXMLString(
                R"(<texture type="image"><string name="filename" value="/nonexistent.png"/></texture>)");
        }),
        Contains("/nonexistent.png") && Contains("no such file"));
    CHECK_THAT(errorOf([] {
                   loadFromXMLString(
                       R"(<texture type="checkerboard"><float name="scale" value="0"/></texture>)");
               }),
               Contains("'scale' must be positive"));
}

TEST_CASE("A texture holding NaN is refused, naming the file and pixel", "[texture]") {
    TempDir dir;
    Bitmap image(Eigen::Vector2i(3, 2));
    image(1, 2) = Color3f(0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f);
    const std::string file = (dir.path() / "nan.exr").string();
    image.saveEXR(file);
    CHECK_THAT(errorOf([&] { loadTextureImage(file, ColorSpace::Auto); }),
               Contains("nan.exr' holds a NaN or infinite value at pixel (2, 1)"));
}

TEST_CASE("scale and mix textures combine their inputs as pbrt-v4 defines them", "[textures]") {
    auto texture = [](const std::string &xml) {
        auto bsdf = std::dynamic_pointer_cast<BSDF>(
            loadFromXMLString("<bsdf type=\"diffuse\">" + xml + "</bsdf>"));
        REQUIRE(bsdf);
        return bsdf->textures().all().front();
    };
    const auto scaled = texture(R"(<texture type="scale" name="albedo">
        <texture type="checkerboard" name="tex"><color name="color0" value="0.8"/>
            <color name="color1" value="0.4"/><float name="scale" value="1"/></texture>
        <color name="scale" value="0.5, 1, 0.25"/></texture>)");
    CHECK(scaled->eval(TextureQuery(Point2f(0.25f, 0.25f))).isApprox(Color3f(0.4f, 0.8f, 0.2f)));
    CHECK(scaled->eval(TextureQuery(Point2f(1.25f, 0.25f))).isApprox(Color3f(0.2f, 0.4f, 0.1f)));
    CHECK(scaled->average().isApprox(Color3f(0.3f, 0.6f, 0.15f)));
    CHECK_FALSE(scaled->isConstant());

    const auto mixed = texture(R"(<texture type="mix" name="albedo">
        <color name="tex1" value="1, 0, 0"/><color name="tex2" value="0, 0, 1"/>
        <texture type="checkerboard" name="amount"><color name="color0" value="0.25"/>
            <color name="color1" value="1"/><float name="scale" value="1"/></texture></texture>)");
    CHECK(mixed->eval(TextureQuery(Point2f(0.5f, 0.5f))).isApprox(Color3f(0.75f, 0.0f, 0.25f)));
    CHECK(mixed->eval(TextureQuery(Point2f(1.5f, 0.5f))).isApprox(Color3f(0.0f, 0.0f, 1.0f)));
    const auto constant = texture(R"(<texture type="mix" name="albedo">
        <color name="tex1" value="0.2"/><color name="tex2" value="0.6"/>
        <float name="amount" value="0.5"/></texture>)");
    CHECK(constant->isConstant());
    CHECK(constant->average().isApprox(Color3f(0.4f)));
}
