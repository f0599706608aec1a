// The helpers of Nori 2's common.h (include/nori/common.h, second half), for course code.
#include <nori/common.h>
#include <nori/vector.h>

#include <filesystem/resolver.h>

#include <cctype>
#include <cstring>
#include <thread>

namespace nori {

std::vector<char> detail::printfConversions(std::string_view format) {
    std::vector<char> conversions;
    for (size_t i = 0; i < format.size(); ++i) {
        if (format[i] != '%')
            continue;
        if (++i < format.size() && format[i] == '%')
            continue; // "%%"
        // %[flags][width][.precision][length]conversion; a '*' takes an int argument.
        while (i < format.size() && std::strchr("-+ #0", format[i]) != nullptr)
            ++i;
        for (bool precision = false;; precision = true) {
            if (i < format.size() && format[i] == '*') {
                conversions.push_back('d');
                ++i;
            }
            while (i < format.size() && std::isdigit(static_cast<unsigned char>(format[i])))
                ++i;
            if (precision || i >= format.size() || format[i] != '.')
                break;
            ++i;
        }
        while (i < format.size() && std::strchr("hlLqjzt", format[i]) != nullptr)
            ++i;
        if (i < format.size())
            conversions.push_back(format[i]);
    }
    return conversions;
}

int getCoreCount() {
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

std::string indent(const std::string &text, int amount) {
    const std::string spacer(static_cast<size_t>(std::max(amount, 0)), ' ');
    std::string result;
    result.reserve(text.size());
    for (char c : text) {
        result += c;
        if (c == '\n')
            result += spacer;
    }
    return result;
}

bool toBool(const std::string &text) {
    const std::string value = toLower(trim(text));
    if (value == "true")
        return true;
    if (value == "false")
        return false;
    throw NoriException("could not parse boolean value '{}'", text);
}

unsigned int toUInt(const std::string &text) {
    const int value = toInt(text, "unsigned integer");
    if (value < 0)
        throw NoriException("could not parse '{}' as an unsigned integer", text);
    return static_cast<unsigned int>(value);
}

Eigen::Vector3f toVector3f(const std::string &text) {
    const std::vector<float> values = toFloatList(text, "vector");
    if (values.size() != 3)
        throw NoriException("could not parse '{}' as a 3D vector: it has {} components", text,
                            values.size());
    return Eigen::Vector3f(values[0], values[1], values[2]);
}

std::string timeString(double milliseconds, bool precise) {
    if (!std::isfinite(milliseconds))
        return "inf";
    static const char *const kUnits[] = {"ms", "s", "m", "h", "d"};
    static const double kFactors[] = {1000, 60, 60, 24};
    int unit = 0;
    double value = milliseconds;
    while (unit < 4 && value > kFactors[unit]) {
        value /= kFactors[unit];
        ++unit;
    }
    return fmt::format(precise ? "{:.4f}{}" : "{:.1f}{}", value, kUnits[unit]);
}

std::string memString(size_t bytes, bool precise) {
    static const char *const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
    double value = static_cast<double>(bytes);
    int unit = 0;
    while (unit < 5 && value > 1024.0) {
        value /= 1024.0;
        ++unit;
    }
    if (unit == 0)
        return fmt::format("{} B", bytes);
    return fmt::format(precise ? "{:.4f} {}" : "{:.1f} {}", value, kUnits[unit]);
}

Vector3f sphericalDirection(float theta, float phi) {
    return Vector3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                    std::cos(theta));
}

Point2f sphericalCoordinates(const Vector3f &direction) {
    float phi = std::atan2(direction.y(), direction.x());
    if (phi < 0.0f)
        phi += 2.0f * kPi;
    return Point2f(std::acos(std::clamp(direction.z(), -1.0f, 1.0f)), phi);
}

filesystem::resolver *getFileResolver() {
    static filesystem::resolver resolver;
    return &resolver;
}

} // namespace nori
