// The object model: every plugin is a NoriObject, created by name through the
// NoriObjectFactory from a PropertyList, then given its children and activated.
#pragma once

#include <nori/proplist.h>

#include <functional>
#include <memory>
#include <vector>

namespace nori {

class NoriObject : public std::enable_shared_from_this<NoriObject> {
public:
    enum EClassType {
        EScene = 0,
        EMesh,
        EBSDF,
        EPhaseFunction,
        EEmitter,
        EMedium,
        ETexture,
        ECamera,
        EIntegrator,
        ESampler,
        ETest,
        EReconstructionFilter,
        EClassTypeCount
    };

    virtual ~NoriObject() = default;

    virtual EClassType getClassType() const = 0;
    /// Attaches a child object. `name` is the child's `name=` attribute in the XML (how
    /// a child binds to a slot, e.g. a texture named "albedo"), or empty. The default
    /// accepts nothing; a parent throws a NoriException naming what it cannot take.
    virtual void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name);
    /// Nori 2's addChild, which course plugins override: the default addChild above keeps
    /// the child alive (owned by this object) and passes it here. The default throws.
    virtual void addChild(NoriObject *child);
    /// Called on a child when it is attached to its parent.
    virtual void setParent(NoriObject *parent) { (void)parent; }
    /// Offers this object to a parent that takes it without knowing its type: a shape
    /// (geometry) holds a BSDF, an area light and media (render), which attach
    /// themselves, so that the lower layer never names the higher one. Returns whether
    /// it attached; the default attaches nowhere. Needs the object to be owned by a
    /// shared_ptr (as everything the factory makes is).
    virtual bool attachTo(NoriObject &parent, const std::string &name) {
        (void)parent, (void)name;
        return false;
    }
    /// Called once all children are attached: compute derived data, check completeness.
    virtual void activate() {}
    virtual std::string toString() const = 0;
    /// Reads the properties that every plugin of a kind accepts (a sampler's
    /// `sampleCount`, an integrator's `aovs`): the factory calls it on the base class
    /// right after the plugin's constructor, so no plugin has to read them itself.
    virtual void readCommonProperties(const PropertyList &props) { (void)props; }

    /// The name the plugin was created by ("roughconductor"), set by the factory.
    const std::string &pluginName() const { return m_pluginName; }
    void setPluginName(const std::string &name) { m_pluginName = name; }
    /// The element's `name=` attribute ("albedo"), as ETH's Nori calls it; empty if none.
    const std::string &getIdName() const { return m_idName; }
    void setIdName(const std::string &name) { m_idName = name; }

    /// The XML tag of a class type ("bsdf", "rfilter", ...).
    static std::string classTypeName(EClassType type);
    /// The class type of an XML tag, or EClassTypeCount when the tag is not an object.
    static EClassType classTypeFromName(const std::string &tag);

private:
    std::string m_pluginName;
    std::string m_idName;
    /// Children handed to Nori 2's addChild(NoriObject *), which takes no ownership.
    std::vector<std::shared_ptr<NoriObject>> m_rawChildren;
};

/// The prefix of a plugin name that means our plugin, not a user's that replaced it.
inline constexpr const char *kBuiltinPrefix = "builtin:";

/// Registry from plugin kind and name to constructor (a name is unique within a kind).
class NoriObjectFactory {
public:
    using Constructor = std::function<std::shared_ptr<NoriObject>(const PropertyList &)>;

    struct Entry {
        NoriObject::EClassType type;
        Constructor constructor;
        std::string sourceFile; ///< where it was registered (__FILE__), for its doc comment
    };

    /// Registers a plugin; throws NoriException when the kind already has that name.
    static void registerClass(const std::string &name, NoriObject::EClassType type,
                              Constructor constructor, const std::string &sourceFile = "");
    /// As registerClass, for static initialisation (where throwing would abort): a
    /// second registration of a name is kept aside for checkRegistry().
    static bool registerStatic(const std::string &name, NoriObject::EClassType type,
                               Constructor constructor, const char *sourceFile) noexcept;
    /// Records the source files of the plugins the project ships (plugins/builtin/, by the
    /// code the build generates): a plugin of a user's file that registers one of their
    /// names replaces ours.
    static bool registerShippedFiles(const std::vector<const char *> &files) noexcept;
    /// Whether `sourceFile` (as __FILE__ gives it) is one of the project's plugin files.
    static bool isShippedFile(const std::string &sourceFile);
    /// Settles the names registered twice at start-up: a user's plugin that registers the
    /// name of one of ours replaces ours (see replacements()); any other name registered
    /// twice (two of ours, two of a user's) throws NoriException naming both files.
    static void checkRegistry();

    /// A plugin of ours that a user's plugin of the same kind and name replaced.
    struct Replacement {
        NoriObject::EClassType type;
        std::string name;
        std::string yourFile, ourFile;
    };
    /// The replacements checkRegistry() made (and useBuiltin() did not undo).
    static std::vector<Replacement> replacements();
    /// Uses our plugin `name` again instead of the user's that replaced it; throws
    /// NoriException when no plugin of that name was replaced.
    static void useBuiltin(const std::string &name);

    /// Constructs a plugin of the expected kind. Throws for unknown names (with a
    /// "did you mean"), for a plugin of another kind, and for unread properties.
    /// "builtin:NAME" (kBuiltinPrefix) is our plugin NAME even when a user's replaced it.
    static std::shared_ptr<NoriObject> createInstance(const std::string &name,
                                                      NoriObject::EClassType expectedType,
                                                      const PropertyList &props);
    /// Every registered plugin, sorted by kind then name.
    static std::vector<std::pair<NoriObject::EClassType, std::string>> registeredClasses();
    /// Whether some kind has a plugin called `name`.
    static bool isRegistered(const std::string &name);
    /// The kinds that have a plugin called `name` (usually one).
    static std::vector<NoriObject::EClassType> kindsOf(const std::string &name);
    /// The registration of the plugin; throws NoriException when there is none.
    static const Entry &entry(NoriObject::EClassType type, const std::string &name);
    /// Removes the plugins called `name`, of every kind.
    static void unregisterClass(const std::string &name);

    /// Called with every plugin createInstance() makes and the properties it was given
    /// (which know what the plugin read): how the doc test sees what plugins read. One
    /// observer at a time; an empty function removes it.
    using Observer = std::function<void(NoriObject::EClassType type, const std::string &name,
                                        const PropertyList &props)>;
    static void setObserver(Observer observer);
};

/// Stores a child in a parent's single slot for it (a scene's camera, a shape's BSDF),
/// throwing when the slot is already taken.
template <typename T>
void setUniqueChild(std::shared_ptr<T> &slot, const std::shared_ptr<NoriObject> &child,
                    const char *parentKind) {
    if (slot)
        throw NoriException("{} takes only one {}", parentKind,
                            NoriObject::classTypeName(child->getClassType()));
    slot = std::static_pointer_cast<T>(child);
}

/// Creates a plugin with default parameters, as a parent does for a missing child
/// (e.g. the default "gaussian" filter of a camera).
template <typename T> std::shared_ptr<T> createDefault(const std::string &name) {
    return std::static_pointer_cast<T>(
        NoriObjectFactory::createInstance(name, T::kClassType, PropertyList()));
}

/// Registers `cls` under `name`. The class must derive from a base class that defines
/// `static constexpr EClassType kClassType` (every base class in include/nori does).
#define NORI_REGISTER_CLASS(cls, name)                                                             \
    static const bool cls##_registered = ::nori::NoriObjectFactory::registerStatic(                \
        name, cls::kClassType,                                                                     \
        [](const ::nori::PropertyList &props) -> std::shared_ptr<::nori::NoriObject> {             \
            return std::make_shared<cls>(props);                                                   \
        },                                                                                         \
        __FILE__);

/// Registers `cls` under another name too (a course's or another renderer's name for the
/// same plugin); its doc comment lists it ("Also registered as: ...").
#define NORI_REGISTER_ALIAS(cls, alias, tag)                                                       \
    static const bool cls##_alias_##tag = ::nori::NoriObjectFactory::registerStatic(               \
        alias, cls::kClassType,                                                                    \
        [](const ::nori::PropertyList &props) -> std::shared_ptr<::nori::NoriObject> {             \
            return std::make_shared<cls>(props);                                                   \
        },                                                                                         \
        __FILE__);

} // namespace nori
