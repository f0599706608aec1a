#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/loadahead.h>
#include <nori/texturecache.h>

#include <map>
#include <mutex>
#include <tuple>

namespace nori {

namespace {

/// The decoded image as texture values: sRGB or power-law decoding where the colour space
/// asks for it.
Bitmap textureValues(ImageFile file, ColorSpace colorSpace, float gamma,
                     const std::string &filename) {
    const bool decodeSRGB =
        colorSpace == ColorSpace::SRGB || (colorSpace == ColorSpace::Auto && file.integerEncoded);
    for (int y = 0; y < file.pixels.height(); ++y)
        for (int x = 0; x < file.pixels.width(); ++x) {
            Color3f &pixel = file.pixels.coeffRef(y, x);
            if (!pixel.allFinite())
                throw NoriException("image '{}' holds a NaN or infinite value at pixel ({}, {})",
                                    filename, x, y);
            if (decodeSRGB)
                pixel = pixel.toLinearRGB();
            else if (colorSpace == ColorSpace::Gamma)
                pixel = pixel.max(0.0f).pow(gamma);
        }
    return std::move(file.pixels);
}

/// The images of textures and environment maps are decoded ahead (LoadAhead), once per
/// file: the cache below serves every texture that names it.
NORI_REGISTER_READER(
    kTextureImageReader, [](const std::string &path) { return std::any(readImageFile(path)); },
    LoadAhead::Sharing::PerPath);

} // namespace

std::shared_ptr<const MIPMap> loadTextureImage(const std::string &filename, ColorSpace colorSpace,
                                               float gamma) {
    if (colorSpace != ColorSpace::Gamma)
        gamma = 1.0f;
    static std::mutex mutex;
    static std::map<std::tuple<std::string, ColorSpace, float>, std::weak_ptr<const MIPMap>> cache;
    const auto key = std::make_tuple(canonicalPathOrSame(filename), colorSpace, gamma);
    std::lock_guard<std::mutex> lock(mutex);
    if (auto cached = cache[key].lock())
        return cached;
    auto mipmap = std::make_shared<const MIPMap>(textureValues(
        LoadAhead::takeOrRead<ImageFile>(kTextureImageReader, filename, readImageFile), colorSpace,
        gamma, filename));
    cache[key] = mipmap;
    return mipmap;
}

} // namespace nori
