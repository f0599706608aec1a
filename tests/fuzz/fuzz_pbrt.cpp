// libFuzzer target of the pbrt-v4 tokenizer and parser (src/import/pbrtparser.cpp): the
// input is read as a scene file (Include and Import refused); every directive must come
// out whole, or the read end in a NoriException.
#include <nori/common.h>
#include <nori/pbrtparser.h>

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    try {
        size_t values = 0;
        nori::pbrt::parseString(std::string_view(reinterpret_cast<const char *>(data), size),
                                "input", [&](const nori::pbrt::Directive &directive) {
                                    for (const auto &parameter : directive.parameters)
                                        values += parameter.numbers.size() +
                                                  parameter.strings.size() + parameter.bools.size();
                                });
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
