// libFuzzer target of the volume-grid readers (Mitsuba .vol and NanoVDB): the input is
// parsed as a grid, looked up at a few points and bounded by a coarse majorant grid; it
// must work or end in a NoriException.
#include <nori/volumegrid.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        // A few hundred bytes of NanoVDB can describe a sparse grid whose dense copy fills
        // VolumeGrid::kMaxValues (4 GiB), beyond libFuzzer's memory and time limits per
        // input: the fuzzer caps it at 2^22 values. The cap's error is tested in [media].
        const nori::VolumeGrid grid =
            nori::VolumeGrid::parse(bytes, "fuzz.grid", "", uint64_t(1) << 22);
        float sum = 0.0f;
        for (int i = 0; i <= 8; ++i) {
            const nori::Point3f u(i / 8.0f, 0.5f, 1.0f - i / 8.0f);
            sum += grid.lookup(u) + grid.lookupColor(u).sum();
        }
        const nori::MajorantGrid majorants(grid, 2, 1.0f);
        if (!(sum >= 0.0f) || majorants.maximum() < 0.0f)
            __builtin_trap(); // values were checked to be finite and non-negative
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
