#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/texturecache.h>

#include <map>
#include <mutex>

namespace nori {

namespace {

/// The decoded image as texture values: sRGB decoding where the colour space asks for it.
Bitmap textureValues(ImageFile file, ColorSpace colorSpace, const std::string &filename) {
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
        }
    return std::move(file.pixels);
}

} // namespace

std::shared_ptr<const MIPMap> loadTextureImage(const std::string &filename, ColorSpace colorSpace) {
    static std::mutex mutex;
    static std::map<std::pair<std::string, ColorSpace>, std::weak_ptr<const MIPMap>> cache;
    const auto key = std::make_pair(canonicalPathOrSame(filename), colorSpace);
    std::lock_guard<std::mutex> lock(mutex);
    if (auto cached = cache[key].lock())
        return cached;
    auto mipmap = std::make_shared<const MIPMap>(
        textureValues(readImageFile(filename), colorSpace, filename));
    cache[key] = mipmap;
    return mipmap;
}

} // namespace nori
