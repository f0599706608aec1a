// libFuzzer target of the XML scene parser: any input must load, or end in a
// NoriException; anything else (a crash, a sanitizer report, another exception, a hang)
// is a bug. Relative file names resolve against the folder of the seed corpus.
#include <nori/parser.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string xml(reinterpret_cast<const char *>(data), size);
    try {
        nori::loadFromXMLString(xml, NORI_FUZZ_XML_DIRECTORY);
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of most inputs.
    }
    return 0;
}
