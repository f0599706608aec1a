// Decoding image files read from outside (textures, environment maps, renders to
// compare): PNG, JPEG, Radiance HDR, OpenEXR and PFM, recognised by their first bytes, and
// TGA, which has no signature, by its name (".tga") or its version 2.0 footer. Every
// decoder bounds the image size before allocating and turns any defect of the file into a
// NoriException naming it — never a crash, a hang or a leak (each format has a fuzz target).
#pragma once
#include <nori/bitmap.h>
#include <nori/layeredimage.h>

#include <cstddef>
#include <string>

namespace nori {

/// The pixels of an image file as stored, before any colour conversion.
struct ImageFile {
    Bitmap pixels;
    /// True for 8- and 16-bit formats (PNG, JPEG, TGA): values are the integers scaled to
    /// [0, 1], sRGB-encoded by convention. False for float formats (HDR, EXR): linear.
    bool integerEncoded = false;
    /// A PNG's alpha channel (its value in every colour channel), straight, not
    /// premultiplied; empty for images without one and for the other formats.
    Bitmap alpha;
};

/// Largest image accepted: 2^27 pixels (1.5 GiB as float RGB), each side at most 65536.
constexpr std::size_t kMaxImageFilePixels = std::size_t(1) << 27;

/// Decodes `bytes`, the content of the file `name` (used in messages). Grey images are
/// expanded to RGB; alpha is kept (in ImageFile::alpha) for PNG only. Throws NoriException on any defect, and for
/// images of more than `maxPixels` pixels.
ImageFile decodeImageFile(const std::string &bytes, const std::string &name,
                          std::size_t maxPixels = kMaxImageFilePixels);

/// Most channels an EXR file may have (our renders with every AOV have 17).
constexpr int kMaxEXRChannels = 256;

/// Decodes every channel of an EXR file and its string attributes. Throws NoriException
/// naming the file on any defect, and when its pixels × channels exceed 4 · maxPixels.
LayeredImage decodeLayeredEXR(const std::string &bytes, const std::string &name,
                              std::size_t maxPixels = kMaxImageFilePixels);

/// Reads and decodes an image file (see decodeImageFile).
ImageFile readImageFile(const std::string &filename);

} // namespace nori
