// libFuzzer target of the TGA decoder (src/image/imagefile.cpp): a TGA has no signature,
// so the input is named as a .tga file; it must decode or end in a NoriException, within
// 2^20 pixels.
#include <nori/imagefile.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    try {
        nori::decodeImageFile(std::string(reinterpret_cast<const char *>(data), size), "fuzz.tga",
                              std::size_t(1) << 20);
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
