// libFuzzer target of the pbrt-v4 importer's reading layers (src/import/pbrtparser.cpp and
// pbrtscene.cpp): the input is read as a scene file (Include and Import refused) and its
// directives applied to pbrt-v4's graphics state; it must come out as a scene description
// or end in a NoriException.
#include <nori/common.h>
#include <nori/pbrtscene.h>

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    try {
        nori::pbrt::readSceneString(std::string_view(reinterpret_cast<const char *>(data), size),
                                    "input");
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
