// Reconstruction filters, image blocks and image files.
#include <nori/bitmap.h>
#include <nori/imageblock.h>
#include <nori/layeredimage.h>
#include <nori/rfilter.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::TempDir;

namespace {

std::shared_ptr<ReconstructionFilter> makeFilter(const std::string &name,
                                                 const PropertyList &props = PropertyList()) {
    return std::static_pointer_cast<ReconstructionFilter>(
        NoriObjectFactory::createInstance(name, NoriObject::EReconstructionFilter, props));
}

/// Composite Simpson's rule on [a, b] with n (even) intervals.
template <typename F> double simpson(F f, double a, double b, int n) {
    const double h = (b - a) / n;
    double sum = f(a) + f(b);
    for (int i = 1; i < n; ++i)
        sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
    return sum * h / 3.0;
}

} // namespace

TEST_CASE("Every reconstruction filter integrates to 1 over its support", "[filter]") {
    PropertyList wide;
    wide.setFloat("radius", 3.0f);
    PropertyList gaussianNarrow;
    gaussianNarrow.setFloat("stddev", 0.25f);
    struct Case {
        const char *name;
        PropertyList props;
    };
    for (const Case &c :
         {Case{"box", {}}, Case{"tent", {}}, Case{"gaussian", {}}, Case{"mitchell", {}},
          Case{"box", wide}, Case{"tent", wide}, Case{"gaussian", wide}, Case{"mitchell", wide},
          Case{"gaussian", gaussianNarrow}}) {
        auto filter = makeFilter(c.name, c.props);
        const float r = filter->getRadius();
        // The box and tent have kinks at 0 and ±r; splitting there keeps Simpson exact
        // for piecewise polynomials up to degree 3, so 1e-4 bounds only round-off and
        // the Gaussian's smooth truncation error.
        double integral =
            simpson([&](double x) { return filter->eval(static_cast<float>(x)); }, -r, 0.0, 2000) +
            simpson([&](double x) { return filter->eval(static_cast<float>(x)); }, 0.0, r, 2000);
        INFO(c.name << " radius " << r);
        CHECK(integral == Approx(1.0).margin(1e-4));
        CHECK(filter->eval(r * 1.01f) == 0.0f);
    }
}

TEST_CASE("Filters reject a non-positive radius", "[filter]") {
    PropertyList props;
    props.setFloat("radius", -1.0f);
    CHECK_THAT(errorOf([&] { makeFilter("tent", props); }),
               Contains("tent filter: 'radius' must lie in (0, 32] pixels, got -1"));
}

TEST_CASE("An image block reproduces a constant image with any filter", "[filter]") {
    for (const char *name : {"box", "tent", "gaussian", "mitchell"}) {
        auto filter = makeFilter(name);
        ImageBlock image(Vector2i(8, 6), filter.get());
        // Two blocks covering the image, splatted separately and merged.
        for (int half = 0; half < 2; ++half) {
            ImageBlock block(Vector2i(4, 6), filter.get());
            block.setOffset(Point2i(4 * half, 0));
            for (int y = 0; y < 6; ++y)
                for (int x = 0; x < 4; ++x)
                    for (int s = 0; s < 4; ++s) // stratified positions inside the pixel
                        block.put(Point2f(4 * half + x + 0.25f + 0.5f * (s % 2),
                                          y + 0.25f + (s >= 2 ? 0.5f : 0.0f)),
                                  Color3f(0.5f, 1.0f, 2.0f));
            image.put(block);
        }
        Bitmap bitmap = image.toBitmap();
        INFO(name);
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 8; ++x)
                CHECK(bitmap(y, x).isApprox(Color3f(0.5f, 1.0f, 2.0f), 1e-5f));
    }
}

TEST_CASE("EXR files round-trip exactly, PNG within 8-bit quantisation", "[image]") {
    TempDir dir;
    Bitmap image(Eigen::Vector2i(5, 3));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            image(y, x) = Color3f(0.1f * x, 0.3f * y, 0.123456f + x * y);
    const std::string exr = (dir.path() / "image.exr").string();
    image.saveEXR(exr);
    Bitmap loaded = Bitmap::load(exr);
    REQUIRE(loaded.width() == 5);
    REQUIRE(loaded.height() == 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            CHECK((loaded(y, x) == image(y, x)).all());

    // RGBA, as Blender and most tools write them: the colour loads, alpha is ignored.
    LayeredImage rgba(Eigen::Vector2i(5, 3));
    rgba.addLayer("", {"R", "G", "B"}, image);
    rgba.addChannel("A", LayeredImage::Channel::Constant(3, 5, 0.5f));
    CHECK(rgba.channelsOf("") == std::vector<std::string>{"R", "G", "B", "A"});
    const std::string rgbaFile = (dir.path() / "rgba.exr").string();
    rgba.saveEXR(rgbaFile);
    const Bitmap colour = Bitmap::load(rgbaFile);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            CHECK((colour(y, x) == image(y, x)).all());

    const std::string png = (dir.path() / "image.png").string();
    image.savePNG(png);
    Bitmap fromPng = Bitmap::load(png);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) {
            Color3f expected = image(y, x).min(1.0f);
            // Half a step of 1/255 in sRGB is at most ~0.0049 in linear (near white).
            CHECK(((fromPng(y, x) - expected).abs() <= 0.005f).all());
        }
}

TEST_CASE("sRGB conversion is inverted by toLinearRGB", "[image]") {
    for (float v : {0.0f, 0.001f, 0.0031308f, 0.2f, 0.5f, 1.0f}) {
        Color3f c(v);
        CHECK(c.toSRGB().toLinearRGB().isApprox(c, 1e-5f));
    }
    CHECK(Color3f(0.5f).toSRGB().r() == Approx(0.735357f).epsilon(1e-5));
}

TEST_CASE("toLinearRGB looks up 8-bit values and computes the rest, to the bit", "[image]") {
    // The sRGB decoding (IEC 61966-2-1) as it is computed.
    auto decoded = [](float value) {
        return value <= 0.04045f ? value * (1.0f / 12.92f)
                                 : std::pow((value + 0.055f) * (1.0f / 1.055f), 2.4f);
    };
    auto exact = [&](float value) {
        const float linear = Color3f(value, 0.5f, value).toLinearRGB().r();
        return linear == decoded(value) || (std::isnan(linear) && std::isnan(value));
    };
    // The values decoders write for 8-bit samples (both roundings), 16-bit samples, their
    // neighbours one ulp away, and values no image holds.
    for (int k = 0; k < 256; ++k) {
        const float product = static_cast<float>(k) * (1.0f / 255.0f),
                    quotient = static_cast<float>(k) / 255.0f;
        for (float value :
             {product, quotient, std::nextafter(product, 2.0f), std::nextafter(quotient, -1.0f)}) {
            INFO(k << ": " << value);
            CHECK(exact(value));
        }
    }
    for (int k = 0; k < 65536; k += 97)
        CHECK(exact(static_cast<float>(k) * (1.0f / 65535.0f)));
    for (float value : {-0.5f, 1.5f, 1e6f, -kInfinity, kInfinity, std::nanf("")})
        CHECK(exact(value));
}

TEST_CASE("Luminance uses Nori's Rec. 709 weights", "[image]") {
    CHECK(Color3f(1.0f, 0.0f, 0.0f).getLuminance() == 0.212671f);
    CHECK(Color3f(0.0f, 1.0f, 0.0f).getLuminance() == 0.715160f);
    CHECK(Color3f(0.0f, 0.0f, 1.0f).getLuminance() == 0.072169f);
    CHECK(Color3f(1.0f).getLuminance() == Approx(1.0f));
}

TEST_CASE("Image loading errors name the file", "[image]") {
    TempDir dir;
    CHECK_THAT(errorOf([] { Bitmap::load("/nonexistent/image.exr"); }),
               Contains("cannot open image file '/nonexistent/image.exr': no such file"));
    const std::string bad = dir.write("broken.exr", "not an exr file");
    CHECK_THAT(errorOf([&] { Bitmap::load(bad); }),
               Contains("broken.exr' is not a PNG, JPEG, Radiance HDR, OpenEXR, PFM or TGA image"));
    const std::string tiff = dir.write("image.tiff", "x");
    CHECK_THAT(errorOf([&] { Bitmap::load(tiff); }), Contains("image.tiff' is not a PNG"));
    CHECK_THAT(errorOf([&] { Bitmap::load(dir.path().string()); }),
               Contains("it is a directory, not a file"));

    // A PNG whose IDAT chunk claims 3.5 GB: an error naming the file, not an allocation.
    Bitmap small(Eigen::Vector2i(4, 4));
    const std::string png = (dir.path() / "corrupt.png").string();
    small.savePNG(png);
    std::string bytes;
    {
        std::ifstream in(png, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    // Signature (8 bytes), IHDR chunk (4 + 4 + 13 + 4): the IDAT length starts at 33.
    REQUIRE(bytes.substr(37, 4) == "IDAT");
    bytes[33] = static_cast<char>(0xD5);
    dir.write("corrupt.png", bytes);
    CHECK_THAT(errorOf([&] { Bitmap::load(png); }),
               Contains("PNG image '") && Contains("corrupt.png' is invalid"));
}

TEST_CASE("nori-imgtool diff prints the error metrics and exits 1 above the tolerance",
          "[image][imgtool]") {
    nori::testing::TempDir dir;
    Bitmap reference(Eigen::Vector2i(4, 2)), image(Eigen::Vector2i(4, 2));
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            reference(y, x) = image(y, x) = Color3f(0.5f + 0.1f * x, 0.25f, 2.0f);
    image(1, 2) += Color3f(0.0f, 0.5f, 0.0f); // one channel of one pixel off by 0.5
    const std::string a = (dir.path() / "a.exr").string(), b = (dir.path() / "b.exr").string();
    image.saveEXR(a);
    reference.saveEXR(b);
    const std::string errorPng = (dir.path() / "error.png").string();

    const auto same =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", b, b, "--tolerance", "0"});
    CHECK(same.exitCode == 0);
    CHECK_THAT(same.output, Catch::Contains("rmse 0\n") && Catch::Contains("differing 0\n"));

    const auto differ = nori::testing::runCommand(
        IMGTOOL_EXECUTABLE,
        {"diff", a, b, "--out", errorPng, "--tolerance", "0.01", "--metric", "maxabs"});
    INFO(differ.output);
    CHECK(differ.exitCode == 1);
    // MSE = 0.25 / 24 values; relMSE = 0.25 / (0.25² + 0.01) / 24; PSNR against peak 2.
    CHECK_THAT(differ.output,
               Catch::Contains(fmt::format("rmse {:.9g}\n", std::sqrt(0.25 / 24.0))));
    CHECK_THAT(differ.output,
               Catch::Contains(fmt::format("relmse {:.9g}\n", 0.25 / 0.0725 / 24.0)));
    CHECK_THAT(differ.output, Catch::Contains("maxabs 0.5\n") && Catch::Contains("differing 1\n") &&
                                  Catch::Contains("over tolerance: maxabs 0.5 > 0.01"));
    CHECK_THAT(differ.output,
               Catch::Contains(fmt::format("psnr {:.6g}\n", 10.0 * std::log10(4.0 * 24.0 / 0.25))));
    CHECK(Bitmap::load(errorPng).rows() == 2);
    CHECK(nori::testing::runCommand(IMGTOOL_EXECUTABLE,
                                    {"diff", a, b, "--tolerance", "0.5", "--metric", "maxabs"})
              .exitCode == 0);

    // --crop: the differing pixel (2, 1) alone, and a region without it.
    const auto cropped =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", a, b, "--crop", "2,1,1,1"});
    CHECK_THAT(cropped.output,
               Catch::Contains(fmt::format("rmse {:.9g}\n", std::sqrt(0.25 / 3.0))) &&
                   Catch::Contains("pixels 1\n"));
    CHECK_THAT(
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", a, b, "--crop", "0,0,4,1"}).output,
        Catch::Contains("rmse 0\n") && Catch::Contains("pixels 4\n"));
    const auto outside =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", a, b, "--crop", "3,0,2,2"});
    CHECK(outside.exitCode == 1);
    CHECK_THAT(outside.output, Catch::Contains("--crop 3,0,2,2 does not fit in the 4x2 images"));

    // --exclude-above (and --exclude-rim): a light seen in the reference, and the pixels
    // around it, leave the comparison; the error is the mean over the pixels kept.
    Bitmap litReference = reference, litImage = image;
    litReference(0, 0) = Color3f(10.0f);
    litImage(0, 0) = Color3f(0.0f); // far off, but left out
    const std::string litA = (dir.path() / "lit-a.exr").string(),
                      litB = (dir.path() / "lit-b.exr").string();
    litImage.saveEXR(litA);
    litReference.saveEXR(litB);
    auto excluding = [&](const std::string &rim) {
        return nori::testing::runCommand(
            IMGTOOL_EXECUTABLE, {"diff", litA, litB, "--exclude-above", "5", "--exclude-rim", rim});
    };
    CHECK_THAT(excluding("0").output,
               Catch::Contains(fmt::format("rmse {:.9g}\n", std::sqrt(0.25 / 21.0))) &&
                   Catch::Contains("pixels 7\n") && Catch::Contains("maxabs 0.5\n"));
    CHECK_THAT(excluding("1").output,
               Catch::Contains(fmt::format("rmse {:.9g}\n", std::sqrt(0.25 / 12.0))) &&
                   Catch::Contains("pixels 4\n"));
    CHECK_THAT(excluding("2").output, Catch::Contains("rmse 0\n") && Catch::Contains("pixels 2\n"));
    CHECK_THAT(nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", litA, litB}).output,
               Catch::Contains("maxabs 10\n") && Catch::Contains("pixels 8\n"));
    const auto negativeRim = excluding("-1");
    CHECK(negativeRim.exitCode == 1);
    CHECK_THAT(negativeRim.output, Catch::Contains("--exclude-rim must be 0 or more"));
    const auto nothingLeft = nori::testing::runCommand(
        IMGTOOL_EXECUTABLE, {"diff", litA, litB, "--exclude-above", "0.1"});
    CHECK(nothingLeft.exitCode == 1);
    CHECK_THAT(nothingLeft.output, Catch::Contains("leaves no pixel to compare"));

    Bitmap wide(Eigen::Vector2i(5, 2));
    const std::string c = (dir.path() / "c.exr").string();
    wide.saveEXR(c);
    const auto mismatch = nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", a, c});
    CHECK(mismatch.exitCode == 1);
    CHECK_THAT(mismatch.output, Catch::Contains("is 4x2 but") && Catch::Contains("is 5x2"));
    CHECK_THAT(
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"diff", a, b, "--layer", "albedo"}).output,
        Catch::Contains("albedo"));
}

namespace {

Bitmap scaled(const Bitmap &image, float factor) {
    Bitmap result = image;
    for (Color3f &pixel : result.reshaped())
        pixel *= factor;
    return result;
}

} // namespace

TEST_CASE("nori-imgtool convert round-trips between EXR, PFM, HDR and PNG", "[image][imgtool]") {
    nori::testing::TempDir dir;
    Bitmap image(Eigen::Vector2i(5, 3));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            image(y, x) = Color3f(0.1f * x + 0.01f, 0.3f * y, 0.05f * (x + y) + 0.2f);
    auto path = [&](const char *name) { return (dir.path() / name).string(); };
    auto convert = [&](std::vector<std::string> arguments) {
        arguments.insert(arguments.begin(), "convert");
        const auto result = nori::testing::runCommand(IMGTOOL_EXECUTABLE, arguments);
        INFO(result.output);
        REQUIRE(result.exitCode == 0);
    };
    image.saveEXR(path("in.exr"));

    // Floats survive EXR → PFM → EXR bit for bit.
    convert({path("in.exr"), path("a.pfm")});
    convert({path("a.pfm"), path("a.exr")});
    CHECK(nori::testing::identicalImages(Bitmap::load(path("a.exr")), image));
    // RGBE keeps an 8-bit mantissa per channel under the exponent of the largest: with
    // frexp(largest) = f·2^e, f in [0.5, 1), a step is 2^(e−8). The encoder truncates and
    // the decoder reads m·2^(e−136) (stb_image's pair), so each channel reads below its
    // value by less than one step (at most largest/128: Ward's (m + 0.5) decoding halved
    // the error, but read every map brighter than its peers do).
    convert({path("in.exr"), path("a.hdr")});
    const Bitmap hdr = Bitmap::load(path("a.hdr"));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) {
            int exponent = 0;
            std::frexp(image(y, x).maxCoeff(), &exponent);
            const float step = std::ldexp(1.0f, exponent - 8);
            CAPTURE(x, y, step);
            CHECK((image(y, x) - hdr(y, x)).maxCoeff() < step);
            CHECK((hdr(y, x) - image(y, x)).maxCoeff() <= 1e-6f * image(y, x).maxCoeff());
        }
    // sRGB PNG: each value within half a step of 8-bit sRGB, decoded back to linear.
    convert({path("in.exr"), path("a.png")});
    const Bitmap png = Bitmap::load(path("a.png"));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            CHECK((png(y, x).toSRGB() - image(y, x).toSRGB()).abs().maxCoeff() <=
                  0.5f / 255.0f + 1e-6f);
    // A linear PNG stores the values themselves; read back as linear they are within half a
    // step, and the sRGB reading of the same file is not (the encoding matters).
    convert({path("in.exr"), path("linear.png"), "--encoding", "linear"});
    convert({path("linear.png"), path("linear.pfm"), "--encoding", "linear"});
    convert({path("linear.png"), path("srgb.pfm")});
    const Bitmap linear = Bitmap::load(path("linear.pfm")), srgb = Bitmap::load(path("srgb.pfm"));
    auto largestDifference = [](const Bitmap &a, const Bitmap &b) {
        float largest = 0.0f;
        for (int y = 0; y < a.height(); ++y)
            for (int x = 0; x < a.width(); ++x)
                largest = std::max(largest, (a(y, x) - b(y, x)).abs().maxCoeff());
        return largest;
    };
    CHECK(largestDifference(linear, image) <= 0.5f / 255.0f + 1e-6f);
    CHECK(largestDifference(srgb, image) > 0.05f);
    // --exposure 1 doubles every value; --layer picks an AOV of a layered EXR.
    convert({path("in.exr"), path("bright.pfm"), "--exposure", "1"});
    CHECK(nori::testing::identicalImages(Bitmap::load(path("bright.pfm")), scaled(image, 2.0f)));
    LayeredImage layered(Eigen::Vector2i(5, 3));
    layered.addLayer("", {"R", "G", "B"}, image);
    layered.addLayer("albedo", {"R", "G", "B"}, scaled(image, 0.5f));
    layered.saveEXR(path("layered.exr"));
    convert({path("layered.exr"), path("albedo.exr"), "--layer", "albedo"});
    CHECK(nori::testing::identicalImages(Bitmap::load(path("albedo.exr")), scaled(image, 0.5f)));
}

TEST_CASE("nori-imgtool info prints sizes, layers and statistics", "[image][imgtool]") {
    nori::testing::TempDir dir;
    LayeredImage layered(Eigen::Vector2i(2, 2));
    Bitmap beauty(Eigen::Vector2i(2, 2));
    beauty(0, 0) = Color3f(1.0f, 2.0f, -1.0f);
    beauty(0, 1) = Color3f(3.0f, 2.0f, 0.0f);
    beauty(1, 0) = Color3f(std::nanf(""), 2.0f, 1.0f);
    beauty(1, 1) = Color3f(5.0f, kInfinity, 2.0f);
    layered.addLayer("", {"R", "G", "B"}, beauty);
    LayeredImage::Channel depth(2, 2);
    depth << 1.0f, 2.0f, 3.0f, 6.0f;
    layered.addChannel("depth.Z", depth);
    const std::string file = (dir.path() / "info.exr").string();
    layered.saveEXR(file);
    const auto info = nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"info", file});
    INFO(info.output);
    CHECK(info.exitCode == 0);
    // Statistics over finite values: R has 1, 3, 5 (NaN left out), G 2, 2, 2 (inf left out).
    CHECK_THAT(info.output, Contains("width 2\nheight 2\nlayers (beauty) depth\n"));
    CHECK_THAT(info.output, Contains("\nchannels R G B\nmin 1 2 -1\nmax 5 2 2\nmean 3 2 0.5\n"
                                     "nan 1\ninf 1\n"));
    CHECK_THAT(info.output, Contains("depth.channels Z\ndepth.min 1\ndepth.max 6\ndepth.mean 3\n"
                                     "depth.nan 0\ndepth.inf 0\n"));
    const auto one =
        nori::testing::runCommand(IMGTOOL_EXECUTABLE, {"info", file, "--layer", "depth"});
    CHECK_THAT(one.output, Contains("depth.mean 3\n") && !Contains("\nmean"));
}

TEST_CASE("nori-imgtool convert and info reject bad files with clear errors", "[image][imgtool]") {
    nori::testing::TempDir dir;
    Bitmap image(Eigen::Vector2i(16, 16));
    image.setConstant(Color3f(0.5f));
    const std::string exr = (dir.path() / "good.exr").string();
    image.saveEXR(exr);
    std::string bytes;
    {
        std::ifstream in(exr, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string truncated = dir.write("truncated.exr", bytes.substr(0, bytes.size() / 2));
    auto run = [](const std::vector<std::string> &arguments) {
        return nori::testing::runCommand(IMGTOOL_EXECUTABLE, arguments);
    };
    const std::string out = (dir.path() / "out.png").string();
    for (const auto &result : {run({"convert", truncated, out}), run({"info", truncated})}) {
        CHECK(result.exitCode == 1);
        CHECK_THAT(result.output, Contains("truncated.exr"));
    }
    const auto layer = run({"convert", exr, out, "--layer", "albedo"});
    CHECK(layer.exitCode == 1);
    CHECK_THAT(layer.output, Contains("good.exr: the image has no layer 'albedo' (its layers: "
                                      "(beauty))"));
    CHECK_THAT(run({"info", exr, "--layer", "normal"}).output,
               Contains("good.exr: the image has no layer 'normal'"));
    CHECK_THAT(run({"convert", exr, (dir.path() / "out.tiff").string()}).output,
               Contains("the output's extension must be .exr, .pfm, .hdr or .png"));
    CHECK_THAT(run({"convert", exr, out, "--encoding", "gamma"}).output,
               Contains("--encoding must be srgb or linear, got 'gamma'"));
    CHECK_THAT(run({"convert", (dir.path() / "missing.exr").string(), out}).output,
               Contains("missing.exr"));
    CHECK_FALSE(std::filesystem::exists(out));
}
