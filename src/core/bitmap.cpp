#include <nori/bitmap.h>
#include <nori/filesystem.h>
#include <nori/strutil.h>

#include <stb_image.h>
#include <stb_image_write.h>
#include <tinyexr.h>

#include <filesystem>
#include <memory>
#include <vector>

// Defined in ext/stb_impl.cpp, where stb's state lives.
void noriClearStbFailureReason();

namespace nori {

namespace {

Bitmap loadEXR(const std::string &filename) {
    float *rgba = nullptr;
    int width = 0, height = 0;
    const char *error = nullptr;
    if (LoadEXR(&rgba, &width, &height, filename.c_str(), &error) != TINYEXR_SUCCESS) {
        std::string message = error ? error : "unknown error";
        FreeEXRErrorMessage(error);
        throw NoriException("cannot read EXR image '{}': {}", filename, message);
    }
    std::unique_ptr<float, decltype(&free)> pixels(rgba, &free);
    Bitmap bitmap(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float *pixel = rgba + 4 * (static_cast<size_t>(y) * width + x);
            bitmap.coeffRef(y, x) = Color3f(pixel[0], pixel[1], pixel[2]);
        }
    return bitmap;
}

/// stb's reason for the last failure; some failures leave none.
std::string stbFailureReason() {
    const char *reason = stbi_failure_reason();
    return reason ? reason : "stb_image rejected the data without giving a reason";
}

Bitmap loadWithStb(const std::string &filename, bool isHDR) {
    int width = 0, height = 0, channels = 0;
    Bitmap bitmap;
    noriClearStbFailureReason();
    if (isHDR) {
        float *data = stbi_loadf(filename.c_str(), &width, &height, &channels, 3);
        if (!data)
            throw NoriException("cannot read image '{}': {}", filename, stbFailureReason());
        std::unique_ptr<float, decltype(&stbi_image_free)> guard(data, &stbi_image_free);
        bitmap = Bitmap(Eigen::Vector2i(width, height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float *pixel = data + 3 * (static_cast<size_t>(y) * width + x);
                bitmap.coeffRef(y, x) = Color3f(pixel[0], pixel[1], pixel[2]);
            }
    } else {
        unsigned char *data = stbi_load(filename.c_str(), &width, &height, &channels, 3);
        if (!data)
            throw NoriException("cannot read image '{}': {}", filename, stbFailureReason());
        std::unique_ptr<unsigned char, decltype(&stbi_image_free)> guard(data, &stbi_image_free);
        bitmap = Bitmap(Eigen::Vector2i(width, height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const unsigned char *pixel = data + 3 * (static_cast<size_t>(y) * width + x);
                bitmap.coeffRef(y, x) =
                    Color3f(pixel[0] / 255.0f, pixel[1] / 255.0f, pixel[2] / 255.0f).toLinearRGB();
            }
    }
    return bitmap;
}

} // namespace

Bitmap Bitmap::load(const std::string &filename) {
    requireRegularFile(filename, "image file");
    const std::string extension = toLower(std::filesystem::path(filename).extension().string());
    if (extension == ".exr")
        return loadEXR(filename);
    if (extension == ".png" || extension == ".jpg" || extension == ".jpeg" || extension == ".hdr")
        return loadWithStb(filename, extension == ".hdr");
    throw NoriException("image '{}': unsupported file type '{}' (use .exr, .png, .jpg or .hdr)",
                        filename, extension);
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
