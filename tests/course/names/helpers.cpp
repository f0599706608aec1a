// Test data of the build's name check (tests/CMakeLists.txt, course.names-*): registers
// nothing (NORI_REGISTER_CLASS(Commented, "out") in a comment does not count).
namespace nori {
float half(float x) {
    return 0.5f * x;
}
} // namespace nori
