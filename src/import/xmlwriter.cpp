#include "import/xmlwriter.h"

#include <fmt/format.h>

namespace nori::importxml {

std::string number(float value) {
    return fmt::format("{}", value + 0.0f); // + 0: no "-0"
}

std::string triple(const Vector3f &v) {
    return fmt::format("{}, {}, {}", v.x(), v.y(), v.z());
}

pugi::xml_node child(pugi::xml_node parent, const char *tag, const std::string &name,
                     const std::string &value) {
    pugi::xml_node node = parent.append_child(tag);
    if (!name.empty())
        node.append_attribute("name") = name.c_str();
    node.append_attribute("value") = value.c_str();
    return node;
}

void addFloat(pugi::xml_node parent, const std::string &name, float value) {
    child(parent, "float", name, number(value));
}
void addInteger(pugi::xml_node parent, const std::string &name, int value) {
    child(parent, "integer", name, std::to_string(value));
}
void addBoolean(pugi::xml_node parent, const std::string &name, bool value) {
    child(parent, "boolean", name, value ? "true" : "false");
}
void addString(pugi::xml_node parent, const std::string &name, const std::string &value) {
    child(parent, "string", name, value);
}
void addColor(pugi::xml_node parent, const std::string &name, const Color3f &value) {
    child(parent, "color", name, fmt::format("{}, {}, {}", value.r(), value.g(), value.b()));
}
void addPoint(pugi::xml_node parent, const std::string &name, const Vector3f &value) {
    child(parent, "point", name, triple(value));
}
void addVector(pugi::xml_node parent, const std::string &name, const Vector3f &value) {
    child(parent, "vector", name, triple(value));
}

void addTransform(pugi::xml_node parent, const std::string &name, const Eigen::Matrix4d &m) {
    if (m.isIdentity(0.0))
        return;
    pugi::xml_node transform = parent.append_child("transform");
    transform.append_attribute("name") = name.c_str();
    std::string values;
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column)
            values += fmt::format("{}{}", values.empty() ? "" : " ", float(m(row, column)) + 0.0f);
    child(transform, "matrix", "", values);
}

pugi::xml_node addObject(pugi::xml_node parent, const char *tag, const std::string &type,
                         const std::string &name) {
    pugi::xml_node node = parent.append_child(tag);
    node.append_attribute("type") = type.c_str();
    if (!name.empty())
        node.append_attribute("name") = name.c_str();
    return node;
}

void addRef(pugi::xml_node parent, const std::string &id, const std::string &name) {
    pugi::xml_node node = parent.append_child("ref");
    if (!name.empty())
        node.append_attribute("name") = name.c_str();
    node.append_attribute("id") = id.c_str();
}

} // namespace nori::importxml
