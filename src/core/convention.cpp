#include <nori/convention.h>

namespace nori {

CourseConvention readCourseConvention(const PropertyList &props) {
    const std::string name = props.getString("convention", "epfl");
    if (name == "epfl")
        return CourseConvention::EPFL;
    if (name == "eth")
        return CourseConvention::ETH;
    throw NoriException("'convention' must be \"epfl\" (Nori 2's: image x mirrored, sphere "
                        "u in [0, 1]) or \"eth\" (ETH's course: not mirrored, sphere u in "
                        "[-1/2, 1/2]), got '{}'",
                        name);
}

const char *courseConventionName(CourseConvention convention) {
    return convention == CourseConvention::EPFL ? "epfl" : "eth";
}

} // namespace nori
