// libFuzzer target of the glTF reader (src/geometry/gltffile.cpp, through tinygltf): the
// input is parsed as a .gltf (JSON) or .glb (binary) file with external files refused; it
// must load or end in a NoriException.
#include <nori/common.h>
#include <nori/gltffile.h>

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    try {
        nori::parseGltf(std::string_view(reinterpret_cast<const char *>(data), size), "input");
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
