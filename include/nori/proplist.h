// Typed parameters of a plugin, as read from XML. The list remembers which properties
// the plugin read and which names it asked for, so that a property nobody read can be
// reported as an error with a "did you mean" (Nori 2 ignores such typos silently).
#pragma once

#include <nori/color.h>
#include <nori/transform.h>

#include <initializer_list>
#include <map>
#include <memory>
#include <set>
#include <variant>
#include <vector>

namespace nori {

class NoriObject;

class PropertyList {
public:
    /// The last alternative is a named child object bound to a parameter, such as
    /// <texture name="albedo">: the parser stores it here so that the plugin reads it like
    /// any other property (and a misspelled name is reported like any other).
    using Value = std::variant<bool, int, float, std::string, Color3f, Point3f, Point2f, Vector3f,
                               Vector2f, Transform, std::shared_ptr<NoriObject>>;

    /// Adds a property; `location` ("file:line:col") is used in error messages and
    /// `directory` is the folder of the XML file it came from (see getPath).
    /// Setting a name twice is an error.
    void set(const std::string &name, const Value &value, const std::string &location = "",
             const std::string &directory = "");

    /// Adds a property the plugin may read or ignore: checkAllRead() does not report it
    /// (a setting the command line gives every object of a kind, such as --convention).
    void setOptional(const std::string &name, const Value &value, const std::string &location);

    void setBoolean(const std::string &name, bool value) { set(name, value); }
    void setInteger(const std::string &name, int value) { set(name, value); }
    void setFloat(const std::string &name, float value) { set(name, value); }
    void setString(const std::string &name, const std::string &value) { set(name, value); }
    void setColor(const std::string &name, const Color3f &value) { set(name, value); }
    void setPoint(const std::string &name, const Point3f &value) { set(name, value); }
    void setVector(const std::string &name, const Vector3f &value) { set(name, value); }
    void setTransform(const std::string &name, const Transform &value) { set(name, value); }

    // Getters: the one-argument form throws when the property is missing; all throw
    // when it has another type. Reading a property marks it as used.
    bool getBoolean(const std::string &name) const;
    bool getBoolean(const std::string &name, bool defaultValue) const;
    int getInteger(const std::string &name) const;
    int getInteger(const std::string &name, int defaultValue) const;
    /// Accepts an <integer> too: the conversion is exact for the values scenes use.
    float getFloat(const std::string &name) const;
    float getFloat(const std::string &name, float defaultValue) const;
    std::string getString(const std::string &name) const;
    std::string getString(const std::string &name, const std::string &defaultValue) const;
    /// Accepts a <float> or <integer> too, as a grey.
    Color3f getColor(const std::string &name) const;
    Color3f getColor(const std::string &name, const Color3f &defaultValue) const;
    Point3f getPoint(const std::string &name) const;
    Point3f getPoint(const std::string &name, const Point3f &defaultValue) const;
    Point2f getPoint2(const std::string &name) const;
    Point2f getPoint2(const std::string &name, const Point2f &defaultValue) const;
    Vector3f getVector(const std::string &name) const;
    Vector3f getVector(const std::string &name, const Vector3f &defaultValue) const;
    Vector2f getVector2(const std::string &name) const;
    Vector2f getVector2(const std::string &name, const Vector2f &defaultValue) const;
    Transform getTransform(const std::string &name) const;
    Transform getTransform(const std::string &name, const Transform &defaultValue) const;
    /// The object bound to `name` (see Value), or nullptr when there is none.
    std::shared_ptr<NoriObject> getObject(const std::string &name) const;
    /// Whether `name` holds an object (without marking it read).
    bool holdsObject(const std::string &name) const;
    /// Whether `name` holds a <float> or an <integer> (without marking it read).
    bool holdsScalar(const std::string &name) const;

    /// A string property naming a file: a relative path is resolved against the folder
    /// of the XML file that set it (never the working directory).
    std::string getPath(const std::string &name) const;

    /// Whether the property exists; records the name as one the plugin knows.
    bool has(const std::string &name) const;
    /// The spelling of a parameter that the scene uses: `name`, or one of its other
    /// spellings (a course's or another renderer's, e.g. "sigma_a" for "sigmaA"), so that
    /// props.getColor(props.spelling("sigmaA", {"sigma_a"})) reads either. `name` when
    /// none is given; throws NoriException naming both when two are given.
    std::string spelling(const std::string &name,
                         std::initializer_list<const char *> otherSpellings) const;
    /// Whether the property exists, without recording anything (for the parser).
    bool contains(const std::string &name) const { return m_properties.count(name) != 0; }
    /// "file:line:col" of a property, or "" when unknown.
    std::string location(const std::string &name) const;

    /// Properties that were set but never read, in the order of their names.
    std::vector<std::string> unreadProperties() const;
    /// Every name a getter or has() was asked for: the names the plugin understands.
    std::vector<std::string> queriedNames() const;
    /// Throws NoriException for the first unread property, naming the plugin
    /// (e.g. "bsdf 'diffuse'") and the closest name the plugin asked for.
    void checkAllRead(const std::string &pluginDescription) const;

private:
    struct Entry {
        Value value;
        std::string location;
        std::string directory;
        mutable bool read = false;
    };

    /// The value of `name` as a T, or nullptr when absent; throws on a type mismatch.
    template <typename T> const T *find(const std::string &name) const;
    template <typename T> T get(const std::string &name) const;
    template <typename T> T get(const std::string &name, const T &defaultValue) const;
    bool holdsInteger(const std::string &name) const;

    std::map<std::string, Entry> m_properties;
    mutable std::set<std::string> m_queried;
};

} // namespace nori
