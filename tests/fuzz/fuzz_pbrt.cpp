// libFuzzer target of the pbrt-v4 importer (src/import/): the input is read as a scene file
// (Include and Import refused), its directives applied to pbrt-v4's graphics state, and
// the scene mapped onto our XML (pbrtimport.cpp); it must come out as XML or end in a
// NoriException. Files the mapping writes (density grids) go to a folder of the fuzzer's.
#include <nori/common.h>
#include <nori/pbrtimport.h>

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const std::string sideFiles =
        (std::filesystem::temp_directory_path() / ("nori-fuzz-pbrt-" + std::to_string(getpid())))
            .string();
    try {
        const nori::pbrt::Scene scene = nori::pbrt::readSceneString(
            std::string_view(reinterpret_cast<const char *>(data), size), "input");
        nori::pbrt::ConvertOptions options;
        options.sideFileDirectory = sideFiles;
        nori::pbrt::convertScene(scene, options);
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
