// Test data of the build's name check (tests/CMakeLists.txt, course.names-*): registers
// `twice`, as second.cpp does too.
#include <nori/bsdf.h>

namespace nori {
class First : public BSDF {};
NORI_REGISTER_CLASS(First, "twice");
} // namespace nori
