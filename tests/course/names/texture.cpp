// Test data of the build's name check (tests/CMakeLists.txt, course.names-*): registers
// `twice` for another kind of plugin than first.cpp and second.cpp, which is allowed.
#include <nori/texture.h>

namespace nori {
class Twice : public Texture {};
NORI_REGISTER_CLASS(Twice, "twice");
} // namespace nori
