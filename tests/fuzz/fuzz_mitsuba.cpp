// libFuzzer target of the Mitsuba importer (src/import/mitsubaimport.cpp): the input is
// read as a Mitsuba scene file (its <include>s resolved against a folder of the fuzzer's,
// which holds none) and mapped onto our XML; it must come out as XML or end in a
// NoriException.
#include <nori/common.h>
#include <nori/mitsubaimport.h>

#include <cstdint>
#include <filesystem>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const std::string scene =
        (std::filesystem::temp_directory_path() / "nori-fuzz-mitsuba" / "input.xml").string();
    try {
        nori::mitsuba::ConvertOptions options;
        options.defines["reflectance"] = "0.5";
        nori::mitsuba::convertText(std::string(reinterpret_cast<const char *>(data), size), scene,
                                   options);
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
