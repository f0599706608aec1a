#include <nori/object.h>
#include <nori/strutil.h>

#include <map>

namespace nori {

namespace {

const char *kClassTypeNames[NoriObject::EClassTypeCount] = {
    "scene",   "mesh",   "bsdf",       "phase",   "emitter", "medium",
    "texture", "camera", "integrator", "sampler", "test",    "rfilter"};

/// Plugins by kind and name: a name may be used once per kind (the `constant` texture
/// and the `constant` environment emitter).
using RegistryKey = std::pair<NoriObject::EClassType, std::string>;
std::map<RegistryKey, NoriObjectFactory::Entry> &registry() {
    static std::map<RegistryKey, NoriObjectFactory::Entry> entries;
    return entries;
}

std::vector<std::string> &duplicateRegistrations() {
    static std::vector<std::string> duplicates;
    return duplicates;
}

/// "a bsdf", "an integrator".
std::string withArticle(NoriObject::EClassType type) {
    const std::string name = NoriObject::classTypeName(type);
    return (std::string("aeiou").find(name[0]) != std::string::npos ? "an " : "a ") + name;
}

NoriObjectFactory::Observer &observerSlot() {
    static NoriObjectFactory::Observer instance;
    return instance;
}

} // namespace

void NoriObject::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    (void)name;
    addChild(child.get());
    m_rawChildren.push_back(child);
}

void NoriObject::addChild(NoriObject *child) {
    throw NoriException("{} does not accept {} as a child", withArticle(getClassType()),
                        withArticle(child->getClassType()));
}

std::string NoriObject::classTypeName(EClassType type) {
    if (type < 0 || type >= EClassTypeCount)
        return "<unknown>";
    return kClassTypeNames[type];
}

NoriObject::EClassType NoriObject::classTypeFromName(const std::string &tag) {
    for (int i = 0; i < EClassTypeCount; ++i)
        if (tag == kClassTypeNames[i])
            return static_cast<EClassType>(i);
    return EClassTypeCount;
}

void NoriObjectFactory::registerClass(const std::string &name, NoriObject::EClassType type,
                                      Constructor constructor, const std::string &sourceFile) {
    auto [it, inserted] = registry().emplace(RegistryKey(type, name),
                                             Entry{type, std::move(constructor), sourceFile});
    if (!inserted)
        throw NoriException("plugin name '{}' is registered twice as {} (in {} and {})", name,
                            withArticle(type), it->second.sourceFile, sourceFile);
}

bool NoriObjectFactory::registerStatic(const std::string &name, NoriObject::EClassType type,
                                       Constructor constructor, const char *sourceFile) noexcept {
    try {
        registerClass(name, type, std::move(constructor), sourceFile);
        return true;
    } catch (const std::exception &error) {
        try {
            duplicateRegistrations().push_back(error.what());
        } catch (...) {
        }
        return false;
    }
}

void NoriObjectFactory::checkRegistry() {
    std::vector<std::string> duplicates;
    std::swap(duplicates, duplicateRegistrations());
    if (!duplicates.empty())
        throw NoriException("{}", fmt::join(duplicates, "; "));
}

std::shared_ptr<NoriObject> NoriObjectFactory::createInstance(const std::string &name,
                                                              NoriObject::EClassType expectedType,
                                                              const PropertyList &props) {
    auto it = registry().find(RegistryKey(expectedType, name));
    if (it == registry().end()) {
        for (const auto &[key, entry] : registry())
            if (key.second == name)
                throw NoriException("plugin '{}' is {}, not {}", name, withArticle(entry.type),
                                    withArticle(expectedType));
        std::vector<std::string> sameKind;
        for (const auto &[key, entry] : registry())
            if (key.first == expectedType)
                sameKind.push_back(key.second);
        std::string hint = didYouMean(name, sameKind);
        if (hint.empty() && !sameKind.empty())
            hint = fmt::format(" (known {} plugins: {})", NoriObject::classTypeName(expectedType),
                               fmt::join(sameKind, ", "));
        throw NoriException("unknown {} plugin '{}'{}", NoriObject::classTypeName(expectedType),
                            name, hint);
    }
    std::shared_ptr<NoriObject> object = it->second.constructor(props);
    object->setPluginName(name);
    object->readCommonProperties(props);
    if (observerSlot())
        observerSlot()(expectedType, name, props);
    props.checkAllRead(fmt::format("{} '{}'", NoriObject::classTypeName(expectedType), name));
    return object;
}

std::vector<std::pair<NoriObject::EClassType, std::string>> NoriObjectFactory::registeredClasses() {
    std::vector<std::pair<NoriObject::EClassType, std::string>> classes;
    for (const auto &[key, entry] : registry())
        classes.push_back(key);
    return classes; // the map's order: by kind, then name
}

bool NoriObjectFactory::isRegistered(const std::string &name) {
    for (const auto &[key, entry] : registry())
        if (key.second == name)
            return true;
    return false;
}

const NoriObjectFactory::Entry &NoriObjectFactory::entry(NoriObject::EClassType type,
                                                         const std::string &name) {
    auto it = registry().find(RegistryKey(type, name));
    if (it == registry().end())
        throw NoriException("no {} plugin is registered as '{}'", NoriObject::classTypeName(type),
                            name);
    return it->second;
}

std::vector<NoriObject::EClassType> NoriObjectFactory::kindsOf(const std::string &name) {
    std::vector<NoriObject::EClassType> kinds;
    for (const auto &[key, entry] : registry())
        if (key.second == name)
            kinds.push_back(key.first);
    return kinds;
}

void NoriObjectFactory::setObserver(Observer observer) {
    observerSlot() = std::move(observer);
}

void NoriObjectFactory::unregisterClass(const std::string &name) {
    for (auto it = registry().begin(); it != registry().end();)
        it = it->first.second == name ? registry().erase(it) : std::next(it);
}

} // namespace nori
