// Writes the seed corpus of the image fuzz target (tests/fuzz/corpus/image): tiny PNG,
// JPEG, HDR (run-length coded and flat) and EXR (float and half) files, made with the
// writers the project links (stb_image_write, tinyexr).
//   nori-make-image-corpus tests/fuzz/corpus/image
#include <stb_image_write.h>
#include <tinyexr.h>

#include <cstdio>
#include <string>
#include <vector>

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
    if (!ok)
        std::fprintf(stderr, "could not write the corpus to %s\n", argv[1]);
    return ok ? 0 : 1;
}
