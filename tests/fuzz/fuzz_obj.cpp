// libFuzzer target of the OBJ loader: the input is written to a file and loaded as an
// "obj" mesh; it must load or end in a NoriException.
#include <nori/object.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace {

/// A file of this process, rewritten for every input and removed when the process exits.
const std::string &scratchFile() {
    static const std::string path = [] {
        std::atexit([] { std::remove(scratchFile().c_str()); });
        return "/tmp/nori-fuzz-obj-" + std::to_string(getpid()) + ".obj";
    }();
    return path;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    FILE *file = std::fopen(scratchFile().c_str(), "wb");
    if (!file)
        return 0;
    std::fwrite(data, 1, size, file);
    std::fclose(file);
    nori::PropertyList props;
    props.setString("filename", scratchFile());
    try {
        auto mesh = nori::NoriObjectFactory::createInstance("obj", nori::NoriObject::EMesh, props);
        mesh->activate();
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
