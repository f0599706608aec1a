// libFuzzer target of the lens-file reader and the optics built on it: the input is parsed
// as a prescription, focused, its exit pupil tabulated (coarsely) and a few rays traced;
// it must work or end in a NoriException.
#include <nori/lenssystem.h>
#include <nori/object.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string text(reinterpret_cast<const char *>(data), size);
    try {
        nori::LensSystem lens(nori::parseLensPrescription(text, "fuzz.dat"), 0.0, "fuzz.dat");
        lens.focusAt(1.0);
        const nori::ExitPupil pupil(lens, 0.02, 4, 64);
        for (int i = 0; i < 16; ++i) {
            const Eigen::Vector2d film(0.02 * i / 16.0, 0.0);
            double area = 0.0;
            const Eigen::Vector3d rear =
                pupil.sample(film, Eigen::Vector2d(0.25 + i / 32.0, 0.5), &area);
            const Eigen::Vector3d origin(film.x(), film.y(), 0.0);
            nori::LensRay out;
            if (area > 0.0)
                lens.traceFromFilm({origin, (rear - origin).normalized()}, &out);
        }
    } catch (const nori::NoriException &) {
        // A clear error is the expected outcome of malformed input.
    }
    return 0;
}
