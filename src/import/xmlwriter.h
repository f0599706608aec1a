// Writing our scene XML (docs/scene-format.md) with pugixml: what the importers of other
// renderers' scenes (pbrt-v4, Mitsuba) share. Numbers are written so that our parser
// reads back the same floats.
#pragma once

#include <nori/color.h>
#include <nori/vector.h>

#include <Eigen/Core>
#include <pugixml.hpp>

#include <string>

namespace nori::importxml {

/// The shortest text that reads back as `value` ("-0" written as "0").
std::string number(float value);
/// "x, y, z".
std::string triple(const Vector3f &v);

/// Appends <tag name="NAME" value="VALUE"/> (no name attribute when `name` is empty).
pugi::xml_node child(pugi::xml_node parent, const char *tag, const std::string &name,
                     const std::string &value);
void addFloat(pugi::xml_node parent, const std::string &name, float value);
void addInteger(pugi::xml_node parent, const std::string &name, int value);
void addBoolean(pugi::xml_node parent, const std::string &name, bool value);
void addString(pugi::xml_node parent, const std::string &name, const std::string &value);
void addColor(pugi::xml_node parent, const std::string &name, const Color3f &value);
void addPoint(pugi::xml_node parent, const std::string &name, const Vector3f &value);
void addVector(pugi::xml_node parent, const std::string &name, const Vector3f &value);
/// <transform name="NAME"><matrix value="16 numbers, row by row"/></transform>, or nothing
/// for the identity.
void addTransform(pugi::xml_node parent, const std::string &name, const Eigen::Matrix4d &m);
/// Appends <tag type="TYPE" [name="NAME"]> and returns it.
pugi::xml_node addObject(pugi::xml_node parent, const char *tag, const std::string &type,
                         const std::string &name = "");
/// Appends <ref [name="NAME"] id="ID"/>.
void addRef(pugi::xml_node parent, const std::string &id, const std::string &name = "");

} // namespace nori::importxml
