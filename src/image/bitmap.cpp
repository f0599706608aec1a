#include <nori/bitmap.h>
#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/layeredimage.h>

#include <stb_image_write.h>
#include <tinyexr.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

namespace nori {

namespace {

const bool kLittleEndian = [] {
    const uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 1;
}();

/// stb_image_write's output callback: appends to a std::string.
void appendBytes(void *context, void *data, int size) {
    static_cast<std::string *>(context)->append(static_cast<const char *>(data), size_t(size));
}

} // namespace

Bitmap Bitmap::load(const std::string &filename) {
    ImageFile file = readImageFile(filename);
    if (file.integerEncoded)
        for (Color3f &pixel : file.pixels.reshaped())
            pixel = pixel.toLinearRGB();
    return std::move(file.pixels);
}

void Bitmap::saveEXR(const std::string &filename) const {
    LayeredImage image;
    image.addLayer("", {"R", "G", "B"}, *this);
    image.saveEXR(filename);
}

void Bitmap::savePFM(const std::string &filename) const {
    // Little-endian floats (scale −1), rows from the bottom up.
    std::string bytes = fmt::format("PF\n{} {}\n-1\n", width(), height());
    const size_t header = bytes.size();
    bytes.resize(header + static_cast<size_t>(width()) * height() * 3 * sizeof(float));
    char *out = bytes.data() + header;
    for (int y = height() - 1; y >= 0; --y)
        for (int x = 0; x < width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float value = coeff(y, x)[c];
                unsigned char raw[4];
                std::memcpy(raw, &value, 4);
                if (!kLittleEndian)
                    std::reverse(raw, raw + 4);
                std::memcpy(out, raw, 4);
                out += 4;
            }
    writeBinaryFile(filename, bytes, "PFM image");
}

void Bitmap::savePNG(const std::string &filename, float exposure, bool srgb) const {
    const float scale = std::exp2(exposure);
    std::vector<unsigned char> rgb(static_cast<size_t>(width()) * height() * 3);
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x) {
            const Color3f scaled = coeff(y, x) * scale;
            const Color3f encoded = srgb ? scaled.toSRGB() : scaled;
            for (int c = 0; c < 3; ++c) {
                float value = std::isfinite(encoded[c]) ? std::clamp(encoded[c], 0.0f, 1.0f) : 0.0f;
                rgb[3 * (static_cast<size_t>(y) * width() + x) + c] =
                    static_cast<unsigned char>(std::lround(value * 255.0f));
            }
        }
    std::string bytes;
    if (!stbi_write_png_to_func(appendBytes, &bytes, width(), height(), 3, rgb.data(), 3 * width()))
        throw NoriException("cannot write PNG image '{}': the encoder failed", filename);
    writeBinaryFile(filename, bytes, "PNG image");
}

void Bitmap::saveHDR(const std::string &filename) const {
    // RGBE has no sign, NaN or infinity: those become 0, as in the PNG.
    std::vector<float> rgb(static_cast<size_t>(width()) * height() * 3);
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float value = coeff(y, x)[c];
                rgb[3 * (static_cast<size_t>(y) * width() + x) + c] =
                    std::isfinite(value) ? std::max(value, 0.0f) : 0.0f;
            }
    std::string bytes;
    if (!stbi_write_hdr_to_func(appendBytes, &bytes, width(), height(), 3, rgb.data()))
        throw NoriException("cannot write HDR image '{}': the encoder failed", filename);
    writeBinaryFile(filename, bytes, "HDR image");
}

namespace {

void checkSameSize(const Bitmap &image, const Bitmap &reference) {
    if (image.width() != reference.width() || image.height() != reference.height())
        throw NoriException("cannot compare a {}x{} image with a {}x{} one", image.width(),
                            image.height(), reference.width(), reference.height());
}

} // namespace

double meanSquaredError(const Bitmap &image, const Bitmap &reference) {
    checkSameSize(image, reference);
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            sum += (image(y, x) - reference(y, x)).cast<double>().square().sum();
    return sum / (3.0 * image.width() * image.height());
}

double relativeMeanSquaredError(
    const Bitmap &image, const Bitmap &reference,
    const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> *mask) {
    checkSameSize(image, reference);
    if (mask && (mask->rows() != image.rows() || mask->cols() != image.cols()))
        throw NoriException("relativeMeanSquaredError: the mask's size differs from the image's");
    constexpr double kEpsilon = 0.01;
    double sum = 0.0;
    size_t pixels = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            if (mask && !(*mask)(y, x))
                continue;
            const Eigen::Array3d r = reference(y, x).cast<double>();
            sum += ((image(y, x).cast<double>() - r).square() / (r.square() + kEpsilon)).sum();
            ++pixels;
        }
    return pixels > 0 ? sum / (3.0 * static_cast<double>(pixels)) : 0.0;
}

} // namespace nori
