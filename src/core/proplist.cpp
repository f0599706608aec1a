#include <nori/proplist.h>
#include <nori/strutil.h>

#include <filesystem>

namespace nori {

namespace {

/// The XML tag that produces each alternative of PropertyList::Value.
const char *typeName(size_t index) {
    static const char *kNames[] = {"boolean",     "integer",   "float",        "string",
                                   "color",       "point",     "point (2D)",   "vector",
                                   "vector (2D)", "transform", "nested object"};
    return kNames[index];
}

/// Throws a LocatedError when the location is known, else a plain NoriException.
[[noreturn]] void fail(const std::string &location, const std::string &message) {
    if (location.empty())
        throw NoriException(message);
    throw LocatedError(location, message);
}

} // namespace

void PropertyList::set(const std::string &name, const Value &value, const std::string &location,
                       const std::string &directory) {
    auto [it, inserted] = m_properties.emplace(name, Entry{value, location, directory});
    if (!inserted)
        fail(location, fmt::format("property '{}' is specified twice (first at {})", name,
                                   it->second.location.empty() ? "?" : it->second.location));
}

void PropertyList::setOptional(const std::string &name, const Value &value,
                               const std::string &location) {
    set(name, value, location);
    m_properties.at(name).read = true;
}

template <typename T> const T *PropertyList::find(const std::string &name) const {
    m_queried.insert(name);
    auto it = m_properties.find(name);
    if (it == m_properties.end())
        return nullptr;
    const Entry &entry = it->second;
    entry.read = true;
    if (const T *value = std::get_if<T>(&entry.value))
        return value;
    fail(entry.location, fmt::format("property '{}' is a {}, but a {} was expected", name,
                                     typeName(entry.value.index()), typeName(Value(T()).index())));
}

template <typename T> T PropertyList::get(const std::string &name) const {
    if (const T *value = find<T>(name))
        return *value;
    throw NoriException("property '{}' ({}) is required but missing", name,
                        typeName(Value(T()).index()));
}

template <typename T> T PropertyList::get(const std::string &name, const T &defaultValue) const {
    const T *value = find<T>(name);
    return value ? *value : defaultValue;
}

std::shared_ptr<NoriObject> PropertyList::getObject(const std::string &name) const {
    return get<std::shared_ptr<NoriObject>>(name, nullptr);
}

bool PropertyList::holdsObject(const std::string &name) const {
    auto it = m_properties.find(name);
    return it != m_properties.end() &&
           std::holds_alternative<std::shared_ptr<NoriObject>>(it->second.value);
}

bool PropertyList::getBoolean(const std::string &name) const {
    return get<bool>(name);
}
bool PropertyList::getBoolean(const std::string &name, bool defaultValue) const {
    return get<bool>(name, defaultValue);
}
int PropertyList::getInteger(const std::string &name) const {
    return get<int>(name);
}
int PropertyList::getInteger(const std::string &name, int defaultValue) const {
    return get<int>(name, defaultValue);
}
float PropertyList::getFloat(const std::string &name) const {
    if (holdsInteger(name))
        return static_cast<float>(get<int>(name));
    return get<float>(name);
}
float PropertyList::getFloat(const std::string &name, float defaultValue) const {
    if (holdsInteger(name))
        return static_cast<float>(get<int>(name));
    return get<float>(name, defaultValue);
}
std::string PropertyList::getString(const std::string &name) const {
    return get<std::string>(name);
}
std::string PropertyList::getString(const std::string &name,
                                    const std::string &defaultValue) const {
    return get<std::string>(name, defaultValue);
}
Color3f PropertyList::getColor(const std::string &name) const {
    if (holdsScalar(name))
        return Color3f(getFloat(name));
    return get<Color3f>(name);
}
Color3f PropertyList::getColor(const std::string &name, const Color3f &defaultValue) const {
    if (holdsScalar(name))
        return Color3f(getFloat(name));
    return get<Color3f>(name, defaultValue);
}
Point3f PropertyList::getPoint(const std::string &name) const {
    return get<Point3f>(name);
}
Point3f PropertyList::getPoint(const std::string &name, const Point3f &defaultValue) const {
    return get<Point3f>(name, defaultValue);
}
Point2f PropertyList::getPoint2(const std::string &name) const {
    return get<Point2f>(name);
}
Point2f PropertyList::getPoint2(const std::string &name, const Point2f &defaultValue) const {
    return get<Point2f>(name, defaultValue);
}
Vector3f PropertyList::getVector(const std::string &name) const {
    return get<Vector3f>(name);
}
Vector3f PropertyList::getVector(const std::string &name, const Vector3f &defaultValue) const {
    return get<Vector3f>(name, defaultValue);
}
Vector2f PropertyList::getVector2(const std::string &name) const {
    return get<Vector2f>(name);
}
Vector2f PropertyList::getVector2(const std::string &name, const Vector2f &defaultValue) const {
    return get<Vector2f>(name, defaultValue);
}
Transform PropertyList::getTransform(const std::string &name) const {
    return get<Transform>(name);
}
Transform PropertyList::getTransform(const std::string &name, const Transform &defaultValue) const {
    return get<Transform>(name, defaultValue);
}

std::string PropertyList::getPath(const std::string &name) const {
    std::filesystem::path path(getString(name));
    const Entry &entry = m_properties.at(name);
    if (path.is_relative() && !entry.directory.empty())
        path = std::filesystem::path(entry.directory) / path;
    return path.lexically_normal().string();
}

bool PropertyList::holdsInteger(const std::string &name) const {
    auto it = m_properties.find(name);
    return it != m_properties.end() && std::holds_alternative<int>(it->second.value);
}

bool PropertyList::holdsScalar(const std::string &name) const {
    auto it = m_properties.find(name);
    return it != m_properties.end() && (std::holds_alternative<int>(it->second.value) ||
                                        std::holds_alternative<float>(it->second.value));
}

std::string PropertyList::spelling(const std::string &name,
                                   std::initializer_list<const char *> otherSpellings) const {
    std::vector<std::string> given;
    m_queried.insert(name);
    if (contains(name))
        given.push_back(name);
    for (const char *other : otherSpellings) {
        m_queried.insert(other);
        if (contains(other))
            given.push_back(other);
    }
    if (given.size() > 1)
        throw NoriException("'{}' (at {}) and '{}' (at {}) are two spellings of the same "
                            "parameter: give only one",
                            given[0], location(given[0]), given[1], location(given[1]));
    return given.empty() ? name : given.front();
}

bool PropertyList::has(const std::string &name) const {
    m_queried.insert(name);
    return m_properties.count(name) != 0;
}

std::string PropertyList::location(const std::string &name) const {
    auto it = m_properties.find(name);
    return it == m_properties.end() ? "" : it->second.location;
}

std::vector<std::string> PropertyList::unreadProperties() const {
    std::vector<std::string> unread;
    for (const auto &[name, entry] : m_properties)
        if (!entry.read)
            unread.push_back(name);
    return unread;
}

std::vector<std::string> PropertyList::queriedNames() const {
    return std::vector<std::string>(m_queried.begin(), m_queried.end());
}

void PropertyList::checkAllRead(const std::string &pluginDescription) const {
    std::vector<std::string> unread = unreadProperties();
    if (unread.empty())
        return;
    const std::string &name = unread.front();
    const Entry &entry = m_properties.at(name);
    std::vector<std::string> known = queriedNames();
    std::string hint = didYouMean(name, known);
    if (hint.empty()) {
        hint = known.empty() ? " (it takes no parameters)"
                             : fmt::format(" (its parameters: {})", fmt::join(known, ", "));
    }
    fail(entry.location, fmt::format("{} property '{}' is not a parameter of {}{}",
                                     typeName(entry.value.index()), name, pluginDescription, hint));
}

} // namespace nori
