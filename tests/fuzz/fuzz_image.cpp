// libFuzzer target of the image decoders (PNG, JPEG, HDR, EXR with every channel and
// its attributes, PFM; src/image/imagefile.cpp) and of the header of a split render's
// part (src/app/renderpart.cpp):
// any input must decode or end in a NoriException, within 2^20 pixels.
#include "app/renderpart.h"
#include <nori/imagefile.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    try {
        nori::decodeImageFile(std::string(reinterpret_cast<const char *>(data), size), "fuzz",
                              std::size_t(1) << 20);
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    try {
        const nori::LayeredImage image = nori::decodeLayeredEXR(
            std::string(reinterpret_cast<const char *>(data), size), "fuzz", std::size_t(1) << 20);
        nori::readPartHeader(image, "fuzz");
    } catch (const nori::NoriException &) {
    }
    return 0;
}
