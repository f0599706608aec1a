// An RGB image of floats, with EXR, PFM and HDR (linear) and PNG (sRGB, 8 bit) input
// and output.
#pragma once

#include <nori/color.h>

#include <Eigen/Core>

namespace nori {

class Bitmap : public Eigen::Array<Color3f, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> {
public:
    using Base = Eigen::Array<Color3f, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    Bitmap() = default;
    /// A black image of the given size (x = width, y = height).
    explicit Bitmap(const Eigen::Vector2i &size) : Base(size.y(), size.x()) {
        setConstant(Color3f(0.0f));
    }

    int width() const { return static_cast<int>(cols()); }
    int height() const { return static_cast<int>(rows()); }

    /// Loads an EXR, PNG, JPEG or HDR file (recognised by its content; see imagefile.h).
    /// 8- and 16-bit formats are taken as sRGB and converted to linear. Throws
    /// NoriException naming the file on failure.
    static Bitmap load(const std::string &filename);
    /// Writes all channels as 32-bit float linear RGB.
    void saveEXR(const std::string &filename) const;
    /// Writes a portable float map (linear RGB, little-endian), as Intel Open Image
    /// Denoise's example tool reads it.
    void savePFM(const std::string &filename) const;
    /// Writes 8-bit sRGB of the values scaled by 2^exposure, clamping to [0, 1]; with
    /// `srgb` false, the scaled values as they are (a linear encoding, for data).
    void savePNG(const std::string &filename, float exposure = 0.0f, bool srgb = true) const;
    /// Writes Radiance RGBE (.hdr): linear, a shared 8-bit exponent per pixel (Ward 1991).
    void saveHDR(const std::string &filename) const;
};

/// The mean over pixels and channels of (image − reference)²; the sizes must agree.
double meanSquaredError(const Bitmap &image, const Bitmap &reference);

/// The relative MSE, the mean over pixels and channels of (image − reference)² /
/// (reference² + ε), which weighs dark and bright regions alike (ε = 0.01, as in
/// Rousselle et al. 2011 and Bitterli et al. 2016); pixels where `mask` is false (when
/// given, same size) are left out.
double relativeMeanSquaredError(
    const Bitmap &image, const Bitmap &reference,
    const Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> *mask = nullptr);

} // namespace nori
