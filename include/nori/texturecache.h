// The MIP pyramids of image files, decoded once: every texture that names the same file
// with the same colour space shares one pyramid, which lives as long as one of them does.
#pragma once
#include <nori/mipmap.h>

#include <memory>
#include <string>

namespace nori {

/// How the values of an image file become texture values.
enum class ColorSpace {
    Auto,   ///< sRGB-decode 8- and 16-bit files, take float files as they are
    SRGB,   ///< decode from sRGB
    Linear, ///< take the stored values (normal, roughness and bump maps)
    Gamma   ///< decode by a power law, value^gamma (pbrt-v4's "gamma G", Mitsuba's gamma)
};

/// The LoadAhead reader of the image files loadTextureImage decodes (a LoadAhead::Reader
/// giving an ImageFile, read once per file): a plugin that loads its `filename` through
/// loadTextureImage registers NORI_REGISTER_LOAD_AHEAD(Class, "type", kTextureImageReader).
constexpr const char *kTextureImageReader = "image";

/// The pyramid of `filename` in `colorSpace` (with ColorSpace::Gamma, the exponent
/// `gamma`), from the cache or decoded now. Throws NoriException naming the file when it
/// cannot be read, or holds a NaN or infinity.
std::shared_ptr<const MIPMap> loadTextureImage(const std::string &filename, ColorSpace colorSpace,
                                               float gamma = 1.0f);

} // namespace nori
