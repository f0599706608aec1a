#include <nori/bitmap.h>
#include <nori/imagefile.h>

#include <stb_image_write.h>
#include <tinyexr.h>

#include <filesystem>
#include <memory>
#include <vector>

namespace nori {

Bitmap Bitmap::load(const std::string &filename) {
    ImageFile file = readImageFile(filename);
    if (file.integerEncoded)
        for (Color3f &pixel : file.pixels.reshaped())
            pixel = pixel.toLinearRGB();
    return std::move(file.pixels);
}

void Bitmap::saveEXR(const std::string &filename) const {
    std::vector<float> rgb(static_cast<size_t>(width()) * height() * 3);
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x)
            for (int c = 0; c < 3; ++c)
                rgb[3 * (static_cast<size_t>(y) * width() + x) + c] = coeff(y, x)[c];
    const char *error = nullptr;
    if (SaveEXR(rgb.data(), width(), height(), 3, /*save_as_fp16=*/0, filename.c_str(), &error) !=
        TINYEXR_SUCCESS) {
        std::string message = error ? error : "unknown error";
        FreeEXRErrorMessage(error);
        throw NoriException("cannot write EXR image '{}': {}", filename, message);
    }
}

void Bitmap::savePNG(const std::string &filename, float exposure) const {
    const float scale = std::exp2(exposure);
    std::vector<unsigned char> rgb(static_cast<size_t>(width()) * height() * 3);
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x) {
            Color3f srgb = Color3f(coeff(y, x) * scale).toSRGB();
            for (int c = 0; c < 3; ++c) {
                float value = std::isfinite(srgb[c]) ? std::clamp(srgb[c], 0.0f, 1.0f) : 0.0f;
                rgb[3 * (static_cast<size_t>(y) * width() + x) + c] =
                    static_cast<unsigned char>(std::lround(value * 255.0f));
            }
        }
    if (!stbi_write_png(filename.c_str(), width(), height(), 3, rgb.data(), 3 * width()))
        throw NoriException("cannot write PNG image '{}'", filename);
}

} // namespace nori
