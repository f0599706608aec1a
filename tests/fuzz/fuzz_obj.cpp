// libFuzzer target of the OBJ loader: the input is written to a file and loaded as an
// "obj" mesh; it must load or end in a NoriException.
#include <nori/object.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>

namespace {

/// A file of this process, written for each input and removed after it. (Removed at exit
/// before, it was left behind by runs that did not exit normally: 23 of them in /tmp.)
std::string scratchFile() {
    return "/tmp/nori-fuzz-obj-" + std::to_string(getpid()) + ".obj";
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string path = scratchFile();
    FILE *file = std::fopen(path.c_str(), "wb");
    if (!file)
        return 0;
    std::fwrite(data, 1, size, file);
    std::fclose(file);
    nori::PropertyList props;
    props.setString("filename", path);
    try {
        auto mesh = nori::NoriObjectFactory::createInstance("obj", nori::NoriObject::EMesh, props);
        mesh->activate();
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    std::remove(path.c_str());
    return 0;
}
