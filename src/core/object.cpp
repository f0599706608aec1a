#include <nori/object.h>
#include <nori/strutil.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <set>

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

/// Second registrations of a name, as static initialisation made them; checkRegistry()
/// settles them once every file (and the list of our files) has registered.
std::vector<std::pair<std::string, NoriObjectFactory::Entry>> &secondRegistrations() {
    static std::vector<std::pair<std::string, NoriObjectFactory::Entry>> entries;
    return entries;
}
std::vector<std::string> &registrationErrors() {
    static std::vector<std::string> errors;
    return errors;
}

/// Our plugins that a user's replaced, by kind and name.
std::map<RegistryKey, NoriObjectFactory::Entry> &replacedEntries() {
    static std::map<RegistryKey, NoriObjectFactory::Entry> entries;
    return entries;
}

std::set<std::string> &shippedFiles() {
    static std::set<std::string> files;
    return files;
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

/// Makes the plugin of `entry`, called `name`, and checks that it read every property.
std::shared_ptr<NoriObject> construct(const NoriObjectFactory::Entry &entry,
                                      const std::string &name, NoriObject::EClassType type,
                                      const PropertyList &props) {
    std::shared_ptr<NoriObject> object = entry.constructor(props);
    object->setPluginName(name);
    object->readCommonProperties(props);
    if (observerSlot())
        observerSlot()(type, name, props);
    props.checkAllRead(fmt::format("{} '{}'", NoriObject::classTypeName(type), name));
    return object;
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
        Entry entry{type, std::move(constructor), sourceFile};
        if (!registry().emplace(RegistryKey(type, name), entry).second)
            secondRegistrations().emplace_back(name, std::move(entry));
        return true;
    } catch (const std::exception &error) {
        try {
            registrationErrors().push_back(error.what());
        } catch (...) {
        }
        return false;
    }
}

bool NoriObjectFactory::registerShippedFiles(const std::vector<const char *> &files) noexcept {
    try {
        for (const char *file : files)
            shippedFiles().insert(std::filesystem::path(file).lexically_normal().string());
        return true;
    } catch (...) {
        return false;
    }
}

bool NoriObjectFactory::isShippedFile(const std::string &sourceFile) {
    return shippedFiles().count(std::filesystem::path(sourceFile).lexically_normal().string()) != 0;
}

void NoriObjectFactory::checkRegistry() {
    std::vector<std::string> errors;
    std::swap(errors, registrationErrors());
    std::vector<std::pair<std::string, Entry>> seconds;
    std::swap(seconds, secondRegistrations());
    for (auto &[name, second] : seconds) {
        const RegistryKey key(second.type, name);
        Entry &first = registry().at(key);
        const bool firstOurs = isShippedFile(first.sourceFile),
                   secondOurs = isShippedFile(second.sourceFile);
        if (firstOurs && !secondOurs) {
            replacedEntries()[key] = std::move(first);
            first = std::move(second);
        } else if (!firstOurs && secondOurs) {
            replacedEntries()[key] = std::move(second);
        } else {
            errors.push_back(
                fmt::format("plugin name '{}' is registered twice as {} (in {} and {})", name,
                            withArticle(second.type), first.sourceFile, second.sourceFile));
        }
    }
    if (!errors.empty())
        throw NoriException("{}", fmt::join(errors, "; "));
}

std::vector<NoriObjectFactory::Replacement> NoriObjectFactory::replacements() {
    std::vector<Replacement> result;
    for (const auto &[key, ours] : replacedEntries())
        result.push_back({key.first, key.second, registry().at(key).sourceFile, ours.sourceFile});
    return result;
}

void NoriObjectFactory::useBuiltin(const std::string &name) {
    bool found = false;
    for (auto it = replacedEntries().begin(); it != replacedEntries().end();) {
        if (it->first.second != name) {
            ++it;
            continue;
        }
        registry().at(it->first) = std::move(it->second);
        it = replacedEntries().erase(it);
        found = true;
    }
    if (!found) {
        std::vector<std::string> replaced;
        for (const auto &[key, entry] : replacedEntries())
            replaced.push_back(key.second);
        throw NoriException(
            "--builtin {}: no plugin of yours replaces one of ours called '{}'{}", name, name,
            replaced.empty() ? std::string(" (none of yours replaces one of ours)")
                             : fmt::format(" (yours replace: {})", fmt::join(replaced, ", ")));
    }
}

std::shared_ptr<NoriObject> NoriObjectFactory::createInstance(const std::string &name,
                                                              NoriObject::EClassType expectedType,
                                                              const PropertyList &props) {
    // "builtin:NAME" is our plugin NAME, also when a user's replaced it (the reference of
    // the automatic tests of a user's plugin).
    const bool builtin = name.rfind(kBuiltinPrefix, 0) == 0;
    if (builtin) {
        const std::string ours = name.substr(std::strlen(kBuiltinPrefix));
        const auto replaced = replacedEntries().find(RegistryKey(expectedType, ours));
        if (replaced != replacedEntries().end())
            return construct(replaced->second, ours, expectedType, props);
        return createInstance(ours, expectedType, props);
    }
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
    return construct(it->second, name, expectedType, props);
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
