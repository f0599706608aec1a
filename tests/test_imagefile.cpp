// Image decoding (src/image/imagefile.cpp): every format round-trips what our writers
// (stb_image_write, tinyexr) produce, and the hostile files that fuzzing found in
// Debian's stb_image and tinyexr end in an error naming the file — not a crash, a hang
// or a leak (the sanitizer build runs these under ASan and LeakSanitizer).
#include "testutil.h"

#include <nori/filesystem.h>
#include <nori/imagefile.h>

#include <catch2/catch.hpp>
#include <stb_image_write.h>
#include <tinyexr.h>

#include <fstream>

using namespace nori;
using namespace nori::testing;
using Catch::Matchers::Contains;

namespace {

/// A small test pattern: value (x + 2y)/(w + 2h) in red, its complement in green, 0.25 blue.
std::vector<unsigned char> pattern8(int width, int height) {
    std::vector<unsigned char> rgb(size_t(3) * width * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int value = 255 * (x + 2 * y) / (width + 2 * height);
            rgb[3 * (y * width + x) + 0] = static_cast<unsigned char>(value);
            rgb[3 * (y * width + x) + 1] = static_cast<unsigned char>(255 - value);
            rgb[3 * (y * width + x) + 2] = 64;
        }
    return rgb;
}

void appendBytes(void *context, void *data, int size) {
    static_cast<std::string *>(context)->append(static_cast<const char *>(data), size);
}

std::string pngBytes(int width, int height, int channels = 3) {
    std::vector<unsigned char> rgb = pattern8(width, height), pixels;
    for (int i = 0; i < width * height; ++i)
        for (int c = 0; c < channels; ++c)
            pixels.push_back(rgb[3 * i + std::min(c, 2)]);
    std::string bytes;
    stbi_write_png_to_func(&appendBytes, &bytes, width, height, channels, pixels.data(),
                           width * channels);
    return bytes;
}

std::string jpegBytes(int width, int height) {
    std::string bytes;
    stbi_write_jpg_to_func(&appendBytes, &bytes, width, height, 3, pattern8(width, height).data(),
                           100);
    return bytes;
}

std::string hdrBytes(const std::vector<float> &rgb, int width, int height) {
    std::string bytes;
    stbi_write_hdr_to_func(&appendBytes, &bytes, width, height, 3, rgb.data());
    return bytes;
}

std::string exrBytes(const std::vector<float> &rgb, int width, int height,
                     const std::string &path) {
    const char *error = nullptr;
    REQUIRE(SaveEXR(rgb.data(), width, height, 3, 0, path.c_str(), &error) == TINYEXR_SUCCESS);
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<float> floatPattern(int width, int height) {
    std::vector<float> rgb(size_t(3) * width * height);
    for (int i = 0; i < width * height; ++i) {
        rgb[3 * i + 0] = 0.001f * (i + 1);
        rgb[3 * i + 1] = 10.0f + i;
        rgb[3 * i + 2] = 0.5f;
    }
    return rgb;
}

} // namespace

TEST_CASE("PNG and JPEG decode to their integers scaled to 0..1, unconverted", "[imagefile]") {
    const std::vector<unsigned char> expected = pattern8(13, 7);
    for (int channels : {1, 2, 3, 4}) {
        CAPTURE(channels);
        const ImageFile png = decodeImageFile(pngBytes(13, 7, channels), "test.png");
        REQUIRE(png.integerEncoded);
        REQUIRE(png.pixels.width() == 13);
        REQUIRE(png.pixels.height() == 7);
        for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 13; ++x) {
                const int i = 3 * (y * 13 + x);
                // Grey (1 or 2 channels) is the red channel copied to all three.
                for (int c = 0; c < 3; ++c)
                    CHECK(png.pixels(y, x)[c] ==
                          Approx(expected[i + (channels < 3 ? 0 : c)] / 255.0f).margin(1e-6));
            }
    }
    const ImageFile jpeg = decodeImageFile(jpegBytes(16, 16), "test.jpg");
    CHECK(jpeg.integerEncoded);
    const std::vector<unsigned char> expected16 = pattern8(16, 16);
    // JPEG is lossy: quality 100 stays within a few levels of 255.
    for (int i = 0; i < 16 * 16; ++i)
        CHECK(jpeg.pixels(i / 16, i % 16)[0] ==
              Approx(expected16[size_t(3) * i] / 255.0f).margin(0.04));
}

TEST_CASE("HDR and EXR decode to linear floats", "[imagefile]") {
    TempDir dir;
    const std::vector<float> rgb = floatPattern(19, 5); // 19 ≥ 8: run-length coded lines
    const ImageFile hdr = decodeImageFile(hdrBytes(rgb, 19, 5), "test.hdr");
    const ImageFile exr =
        decodeImageFile(exrBytes(rgb, 19, 5, (dir.path() / "t.exr").string()), "test.exr");
    CHECK_FALSE(hdr.integerEncoded);
    CHECK_FALSE(exr.integerEncoded);
    for (int i = 0; i < 19 * 5; ++i)
        for (int c = 0; c < 3; ++c) {
            CHECK(exr.pixels(i / 19, i % 19)[c] == rgb[3 * i + c]);
            // RGBE keeps 8 bits of mantissa for the largest channel: relative error < 1/256
            // of it, so the small red channel is compared in absolute terms.
            const size_t first = size_t(3) * i;
            const float largest = std::max({rgb[first], rgb[first + 1], rgb[first + 2]});
            CHECK(hdr.pixels(i / 19, i % 19)[c] == Approx(rgb[3 * i + c]).margin(largest / 128));
        }
}

TEST_CASE("HDR reads values of 8-bit mantissa and shared exponent exactly", "[imagefile]") {
    // Each pixel's channels are m·2^k with m < 256 for the exponent of the largest one: RGBE
    // stores them without rounding, and decoding as m·2^(e−136) (stb_image, pbrt-v4,
    // Walter's rgbe.c) gives them back bit for bit. Ward's (m + 0.5) reads 2.0 as 2.0078.
    const std::vector<float> rgb = {2.0f, 1.0f, 0.5f, 0.75f,       0.5f,        0.25f,
                                    3.0f, 3.0f, 3.0f, 100.0f,      36.0f,       0.0f,
                                    0.0f, 0.0f, 0.0f, 1.0f / 1024, 1.0f / 2048, 0.0f};
    const ImageFile hdr = decodeImageFile(hdrBytes(rgb, 3, 2), "exact.hdr");
    for (int i = 0; i < 3 * 2; ++i)
        for (int c = 0; c < 3; ++c) {
            CAPTURE(i, c);
            CHECK(hdr.pixels(i / 3, i % 3)[c] == rgb[3 * i + c]);
        }
    // The bytes themselves: (128, 64, 32, 130) is (2, 1, 0.5); exponent 0 is black.
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
    const ImageFile bytes =
        decodeImageFile(header + std::string("\x80\x40\x20\x82\xff\xff\xff\x00", 8), "b.hdr");
    CHECK(bytes.pixels(0, 0)[0] == 2.0f);
    CHECK(bytes.pixels(0, 0)[1] == 1.0f);
    CHECK(bytes.pixels(0, 0)[2] == 0.5f);
    CHECK(bytes.pixels(0, 1)[0] == 0.0f);
}

TEST_CASE("Images larger than the limit are refused before decoding", "[imagefile]") {
    CHECK_THAT(errorOf([] { decodeImageFile(pngBytes(64, 64), "big.png", 1000); }),
               Contains("PNG image 'big.png' has an unsupported size 64x64"));
    CHECK_THAT(errorOf([] { decodeImageFile(jpegBytes(64, 64), "big.jpg", 1000); }),
               Contains("JPEG image 'big.jpg' has an unsupported size 64x64"));
    CHECK_THAT(
        errorOf([] { decodeImageFile(hdrBytes(floatPattern(64, 64), 64, 64), "big.hdr", 1000); }),
        Contains("HDR image 'big.hdr' has an unsupported size 64x64"));
}

TEST_CASE("Hostile image files end in an error naming the file", "[imagefile]") {
    TempDir dir;
    SECTION("a JPEG whose Huffman counts sum past 256 (stb_image: out-of-bounds write)") {
        std::string bytes = jpegBytes(16, 16);
        const size_t dht = bytes.find("\xff\xc4");
        REQUIRE(dht != std::string::npos);
        // Marker (2), length (2), class/id (1), then the 16 code counts.
        for (int i = 0; i < 16; ++i)
            bytes[dht + 5 + i] = static_cast<char>(0x40);
        CHECK_THAT(errorOf([&] { decodeImageFile(bytes, "huffman.jpg"); }),
                   Contains("JPEG image 'huffman.jpg' is invalid"));
    }
    SECTION("a truncated run-length HDR scanline (stb_image: endless loop)") {
        const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 16\n";
        // New-style line start, then a run of 20 (> width 16) and a truncated line.
        CHECK_THAT(errorOf([&] {
                       decodeImageFile(header + std::string("\x02\x02\x00\x10\x94\x01", 6),
                                       "overflow.hdr");
                   }),
                   Contains("HDR image 'overflow.hdr' is invalid: a run of scanline 0 overflows"));
        CHECK_THAT(errorOf([&] {
                       decodeImageFile(header + std::string("\x02\x02\x00\x10\x88\x01\x02", 7),
                                       "truncated.hdr");
                   }),
                   Contains("HDR image 'truncated.hdr' is invalid: the file ends early"));
        CHECK_THAT(errorOf([&] {
                       decodeImageFile(header + std::string("\x02\x02\x00\x10\x00", 5), "zero.hdr");
                   }),
                   Contains("overflows the line"));
    }
    SECTION("a 136-byte PNG whose IDAT claims 2 GB (stb_image: a 2 GB allocation)") {
        std::string bytes = pngBytes(4, 4);
        const size_t idat = bytes.find("IDAT");
        REQUIRE(idat != std::string::npos);
        bytes.replace(idat - 4, 4, std::string("\x7f\xff\xff\xff", 4));
        bytes.resize(136, '\0');
        CHECK_THAT(errorOf([&] { decodeImageFile(bytes, "huge-chunk.png"); }),
                   Contains("PNG image 'huge-chunk.png' is invalid"));
    }
    SECTION("an EXR with a corrupt chunk (tinyexr: leaks its channel buffers)") {
        std::string bytes = exrBytes(floatPattern(32, 32), 32, 32, (dir.path() / "c.exr").string());
        // Overwrite the second half of the file: the later scanline chunks' sizes and data.
        for (size_t i = bytes.size() / 2; i < bytes.size(); ++i)
            bytes[i] = static_cast<char>(0xA5);
        CHECK_THAT(errorOf([&] { decodeImageFile(bytes, "chunk.exr"); }),
                   Contains("EXR image 'chunk.exr' is invalid"));
    }
    SECTION("an EXR whose 'type' attribute is not 'scanlineimage' (tinyexr: assert, abort)") {
        const std::string bytes =
            exrBytes(floatPattern(4, 4), 4, 4, (dir.path() / "typed.exr").string());
        // A string attribute inserted first in the header: name, type, size, value.
        auto typeAttribute = [](const std::string &value) {
            const char size[4] = {static_cast<char>(value.size()), 0, 0, 0};
            return std::string("type\0string\0", 12) + std::string(size, 4) + value;
        };
        auto withType = [&](const std::string &value) {
            return bytes.substr(0, 8) + typeAttribute(value) + bytes.substr(8);
        };
        for (const std::string value : {"deeptile", "3-6", "tiledimage"})
            CHECK_THAT(errorOf([&] { decodeImageFile(withType(value), "typed.exr"); }),
                       Contains("EXR image 'typed.exr': its type is '" + value + "'"));
        // The one type a single-part scanline file may declare passes this check (the file
        // fails later only because the insertion moved the chunks its offsets point to).
        CHECK_THAT(errorOf([&] { decodeImageFile(withType("scanlineimage"), "typed.exr"); }),
                   !Contains("its type is"));
        // tinyexr skips a 'type' whose value starts with NUL and keeps the last other one:
        // an empty 'type' first must not hide a foreign one after it (found by the fuzzer).
        auto twice = [&](const std::string &earlier, const std::string &later) {
            return bytes.substr(0, 8) + typeAttribute(earlier) + typeAttribute(later) +
                   bytes.substr(8);
        };
        CHECK_THAT(
            errorOf([&] { decodeImageFile(twice(std::string(3, '\0'), "3-6"), "typed.exr"); }),
            Contains("EXR image 'typed.exr': its type is '3-6'"));
        CHECK_THAT(
            errorOf([&] { decodeImageFile(twice("scanlineimage", "deeptile"), "typed.exr"); }),
            Contains("its type is 'deeptile'"));
    }
    SECTION("truncations of every format") {
        const std::vector<std::pair<std::string, std::string>> files = {
            {"t.png", pngBytes(8, 8)},
            {"t.jpg", jpegBytes(8, 8)},
            {"t.hdr", hdrBytes(floatPattern(8, 8), 8, 8)},
            {"t.exr", exrBytes(floatPattern(8, 8), 8, 8, (dir.path() / "t.exr").string())}};
        for (const auto &file : files) {
            const std::string &name = file.first, &bytes = file.second;
            for (size_t length : {size_t(4), bytes.size() / 3, bytes.size() - 1}) {
                CAPTURE(name, length);
                CHECK_THAT(errorOf([&] { decodeImageFile(bytes.substr(0, length), name); }),
                           Contains(name));
            }
        }
    }
    SECTION("an unknown signature") {
        CHECK_THAT(
            errorOf([] { decodeImageFile("GIF89a......", "anim.gif"); }),
            Contains("'anim.gif' is not a PNG, JPEG, Radiance HDR, OpenEXR, PFM or TGA image"));
    }
}

TEST_CASE("TGA images decode in every layout, and a broken one is located", "[imagefile]") {
    const std::string folder = std::string(NORI_SOURCE_DIR) + "/tests/fuzz/corpus/tga/";
    auto load = [&](const std::string &name) { return readImageFile(folder + name); };
    // Stored bottom-up, BGR: the first stored pixel (red) is the bottom-left one.
    const ImageFile rgb = load("rgb24.tga");
    CHECK(rgb.integerEncoded);
    REQUIRE(rgb.pixels.rows() == 2);
    CHECK(rgb.pixels(1, 0).isApprox(Color3f(1, 0, 0)));
    CHECK(rgb.pixels(1, 1).isApprox(Color3f(0, 1, 0)));
    CHECK(rgb.pixels(0, 0).isApprox(Color3f(0, 0, 1)));
    // Top-left origin (descriptor bit 5), an image id to skip, alpha dropped.
    const ImageFile topLeft = load("rgba32-topleft.tga");
    CHECK(topLeft.pixels(0, 0).isApprox(Color3f(1, 0, 0)));
    CHECK(topLeft.pixels(1, 1).isApprox(Color3f(30, 20, 10) / 255.0f));
    // Run-length packets, grey, a colour map, 5-5-5 bits with a version 2.0 footer.
    const ImageFile rle = load("rle24.tga");
    CHECK(rle.pixels(0, 0).isApprox(Color3f(3, 2, 1) / 255.0f));
    CHECK(rle.pixels(0, 1).isApprox(Color3f(3, 2, 1) / 255.0f));
    CHECK(rle.pixels(0, 2).isApprox(Color3f(7, 8, 9) / 255.0f));
    CHECK(load("grey-rle.tga").pixels(1, 1).isApprox(Color3f(200.0f / 255.0f)));
    const ImageFile mapped = load("mapped.tga");
    CHECK(mapped.pixels(0, 0).isApprox(Color3f(0.0f)));
    CHECK(mapped.pixels(0, 1).isApprox(Color3f(1.0f)));
    const std::string footer = readBinaryFile(folder + "rgb16-footer.tga", "test");
    CHECK(decodeImageFile(footer, "no-extension").pixels(0, 0).isApprox(Color3f(1, 0, 0)));

    std::string truncated = readBinaryFile(folder + "rgb24.tga", "test");
    truncated.resize(truncated.size() - 2);
    CHECK_THAT(errorOf([&] { decodeImageFile(truncated, "cut.tga"); }),
               Catch::Contains("TGA image 'cut.tga' is invalid: the file ends early"));
    std::string runaway = readBinaryFile(folder + "rle24.tga", "test");
    runaway[18] = static_cast<char>(0x85); // a run of 6 in a 3-pixel image
    CHECK_THAT(errorOf([&] { decodeImageFile(runaway, "run.tga"); }),
               Catch::Contains("runs past the end of the image"));
    std::string huge = readBinaryFile(folder + "rgb24.tga", "test");
    huge[12] = huge[13] = huge[14] = huge[15] = static_cast<char>(0xff);
    CHECK_THAT(errorOf([&] { decodeImageFile(huge, "huge.tga"); }),
               Catch::Contains("unsupported size 65535x65535"));
}
