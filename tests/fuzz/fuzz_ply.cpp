// libFuzzer target of the PLY reader (src/geometry/plyfile.cpp): the input is parsed as a
// PLY file, and inflated first when it is gzip-compressed; it must load or end in a
// NoriException.
#include <nori/common.h>
#include <nori/compression.h>
#include <nori/plyfile.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        // The fuzzer's own bound on what a compressed input may inflate to.
        if (nori::isGzip(bytes))
            bytes = nori::inflateBytes(bytes, nori::CompressedFormat::Gzip, "input", 64 << 20);
        nori::parsePLY(bytes, "input");
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
