// Decoding image files read from outside (textures, environment maps): PNG, JPEG,
// Radiance HDR and OpenEXR, recognised by their first bytes. Every decoder bounds the
// image size before allocating and turns any defect of the file into a NoriException
// naming it — never a crash, a hang or a leak (each format has a fuzz target).
#pragma once
#include <nori/bitmap.h>

#include <cstddef>
#include <string>

namespace nori {

/// The pixels of an image file as stored, before any colour conversion.
struct ImageFile {
    Bitmap pixels;
    /// True for 8- and 16-bit formats (PNG, JPEG): values are the integers scaled to
    /// [0, 1], sRGB-encoded by convention. False for float formats (HDR, EXR): linear.
    bool integerEncoded = false;
};

/// Largest image accepted: 2^27 pixels (1.5 GiB as float RGB), each side at most 65536.
constexpr std::size_t kMaxImageFilePixels = std::size_t(1) << 27;

/// Decodes `bytes`, the content of the file `name` (used in messages). Grey images are
/// expanded to RGB and alpha is dropped. Throws NoriException on any defect, and for
/// images of more than `maxPixels` pixels.
ImageFile decodeImageFile(const std::string &bytes, const std::string &name,
                          std::size_t maxPixels = kMaxImageFilePixels);

/// Reads and decodes an image file (see decodeImageFile).
ImageFile readImageFile(const std::string &filename);

} // namespace nori
