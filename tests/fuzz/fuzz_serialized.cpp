// libFuzzer target of the reader of Mitsuba's serialized meshes (src/geometry/
// serializedfile.cpp): every mesh the input's table names must load or end in a
// NoriException.
#include <nori/common.h>
#include <nori/serializedfile.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char *>(data), size);
    for (int index = 0; index < 3; ++index) {
        try {
            nori::parseSerialized(bytes, index, "input");
        } catch (const nori::NoriException &) {
            // A clear error is the expected outcome of malformed input.
        }
    }
    return 0;
}
