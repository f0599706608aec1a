// Test data of the build's name check (tests/CMakeLists.txt, course.names-*): registers
// `twice`, as first.cpp does too.
#include <nori/bsdf.h>

namespace nori {
class Second : public BSDF {};
NORI_REGISTER_CLASS(Second, "twice");
} // namespace nori
