// Writes the seed corpus of the image fuzz target (tests/fuzz/corpus/image): tiny PNG,
// JPEG, HDR (run-length coded and flat), EXR (float, half, and our multi-layer renders
// with attributes, a part of a split render) and PFM files, made with the writers the project
// links (stb_image_write, tinyexr) and its own (LayeredImage, Bitmap::savePFM), and two EXRs
// written byte by byte that declare their chunk count, one rightly, one absurdly.
//   nori-make-image-corpus tests/fuzz/corpus/image
#include "app/renderpart.h"
#include <nori/film.h>
#include <nori/layeredimage.h>

#include <stb_image_write.h>
#include <tinyexr.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace {

/// Appends `value` in the little-endian byte order of EXR files.
template <typename T> void appendLittleEndian(std::string &bytes, T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T)); // the machines we build on are little-endian
    bytes.append(reinterpret_cast<const char *>(raw), sizeof(T));
}

/// A header attribute: name, type, size and value (OpenEXR's "File Layout", "Header").
void appendAttribute(std::string &bytes, const char *name, const char *type,
                     const std::string &value) {
    bytes += name;
    bytes += '\0';
    bytes += type;
    bytes += '\0';
    appendLittleEndian(bytes, static_cast<int32_t>(value.size()));
    bytes += value;
}

/// A 1x1 uncompressed scanline EXR of one float channel Y, written byte by byte, whose
/// header declares `chunkCount` chunks where the file holds one: a reader that sizes its
/// offset table by the attribute alone allocates 8 bytes per declared chunk.
std::string exrDeclaringChunks(int32_t chunkCount) {
    std::string bytes = "\x76\x2f\x31\x01";
    appendLittleEndian(bytes, int32_t(2)); // version 2, single-part scanline
    std::string channels = "Y";
    channels += '\0';
    appendLittleEndian(channels, int32_t(2)); // FLOAT
    channels.append(4, '\0');                 // pLinear and 3 reserved bytes
    appendLittleEndian(channels, int32_t(1)); // x sampling
    appendLittleEndian(channels, int32_t(1)); // y sampling
    channels += '\0';
    appendAttribute(bytes, "channels", "chlist", channels);
    appendAttribute(bytes, "compression", "compression", std::string(1, '\0'));
    const std::string box(16, '\0'); // (0, 0) to (0, 0)
    appendAttribute(bytes, "dataWindow", "box2i", box);
    appendAttribute(bytes, "displayWindow", "box2i", box);
    appendAttribute(bytes, "lineOrder", "lineOrder", std::string(1, '\0'));
    std::string one;
    appendLittleEndian(one, 1.0f);
    appendAttribute(bytes, "pixelAspectRatio", "float", one);
    appendAttribute(bytes, "screenWindowCenter", "v2f", std::string(8, '\0'));
    appendAttribute(bytes, "screenWindowWidth", "float", one);
    std::string count;
    appendLittleEndian(count, chunkCount);
    appendAttribute(bytes, "chunkCount", "int", count);
    bytes += '\0';                                                      // end of the header
    appendLittleEndian(bytes, static_cast<uint64_t>(bytes.size() + 8)); // the offset table
    appendLittleEndian(bytes, int32_t(0));                              // the chunk: line 0,
    appendLittleEndian(bytes, int32_t(4));                              // 4 bytes,
    appendLittleEndian(bytes, 0.5f);                                    // Y = 0.5
    return bytes;
}

} // namespace

int main(int argc, char **argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: nori-make-image-corpus DIRECTORY\n");
        return 2;
    }
    const std::string d = std::string(argv[1]) + "/";
    unsigned char bytes[8 * 8 * 4];
    for (int i = 0; i < 8 * 8 * 4; ++i)
        bytes[i] = static_cast<unsigned char>(i * 37);
    bool ok = stbi_write_png((d + "rgb.png").c_str(), 8, 8, 3, bytes, 24) &&
              stbi_write_png((d + "grey.png").c_str(), 8, 8, 1, bytes, 8) &&
              stbi_write_png((d + "rgba.png").c_str(), 8, 8, 4, bytes, 32) &&
              stbi_write_jpg((d + "rgb.jpg").c_str(), 8, 8, 3, bytes, 90) &&
              stbi_write_jpg((d + "grey.jpg").c_str(), 8, 8, 1, bytes, 90);
    std::vector<float> values(16 * 4 * 3);
    for (size_t i = 0; i < values.size(); ++i)
        values[i] = 0.01f * static_cast<float>(i);
    ok = ok && stbi_write_hdr((d + "rle.hdr").c_str(), 16, 4, 3, values.data()) &&
         stbi_write_hdr((d + "flat.hdr").c_str(), 4, 4, 3, values.data());
    const char *error = nullptr;
    ok =
        ok &&
        SaveEXR(values.data(), 16, 4, 3, 0, (d + "float.exr").c_str(), &error) == TINYEXR_SUCCESS &&
        SaveEXR(values.data(), 16, 4, 3, 1, (d + "half.exr").c_str(), &error) == TINYEXR_SUCCESS;
    nori::Bitmap colour(Eigen::Vector2i(5, 3));
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            colour(y, x) = nori::Color3f(0.1f * x, 0.2f * y, 1.5f);
    nori::LayeredImage layered;
    layered.addLayer("", {"R", "G", "B"}, colour);
    layered.addLayer("normal", {"X", "Y", "Z"}, colour);
    layered.addLayer("depth", {"Z"}, colour);
    layered.attributes["nori/spp"] = "64";
    // A part of a split render: a weight channel and the header nori merge reads.
    nori::LayeredImage part;
    part.addLayer("", {"R", "G", "B"}, colour);
    part.addChannel(nori::kWeightChannel, nori::LayeredImage::Channel::Constant(3, 5, 2.0f));
    nori::PartHeader header;
    header.part = {2, 3};
    header.sceneHash = "0123456789abcdef";
    header.resolution = Eigen::Vector2i(5, 3);
    header.totalSamplesPerPixel = 9;
    header.samples = nori::partSamples(header.part, 9);
    header.filter = "GaussianFilter[radius=2, stddev=0.5]";
    header.scene = "scene.xml";
    nori::writePartHeader(header, part);
    try {
        layered.saveEXR(d + "layers.exr");
        part.saveEXR(d + "part.exr");
        colour.savePFM(d + "rgb.pfm");
    } catch (const nori::NoriException &) {
        ok = false;
    }
    // A grey PFM ("Pf"), big-endian (positive scale), written by hand.
    if (std::FILE *grey = std::fopen((d + "grey.pfm").c_str(), "wb")) {
        const unsigned char pixels[2 * 2 * 4] = {0x3f, 0x80, 0, 0, 0x40, 0, 0, 0,
                                                 0x3f, 0,    0, 0, 0,    0, 0, 0};
        ok = ok && std::fputs("Pf\n2 2\n1.0\n", grey) >= 0 &&
             std::fwrite(pixels, 1, sizeof(pixels), grey) == sizeof(pixels);
        std::fclose(grey);
    } else {
        ok = false;
    }
    // Single-chunk EXRs whose chunkCount is right (1) and absurd (2^31 - 1).
    for (const auto &[file, chunks] :
         {std::pair<const char *, int32_t>{"one-chunk.exr", 1}, {"chunk-count.exr", 2147483647}}) {
        const std::string bytes = exrDeclaringChunks(chunks);
        std::FILE *out = std::fopen((d + file).c_str(), "wb");
        ok =
            ok && out != nullptr && std::fwrite(bytes.data(), 1, bytes.size(), out) == bytes.size();
        if (out != nullptr)
            ok = std::fclose(out) == 0 && ok;
    }
    if (!ok)
        std::fprintf(stderr, "could not write the corpus to %s\n", argv[1]);
    return ok ? 0 : 1;
}
