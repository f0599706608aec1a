// Files read ahead: while the scene parser builds one object after another, helper
// threads already read and decode the files that later elements name (mesh files and
// images), so that a scene of hundreds of PLY files and textures loads on every core.
//
// A reader decodes one kind of file ("ply", "image"); a plugin whose constructor reads
// such a file says so (NORI_REGISTER_LOAD_AHEAD with its class, plugin name and reader)
// and asks for the result by the path it would read (LoadAhead::take). The parser starts a
// read for every element of such a plugin whose `filename` it can resolve without running
// the plugin (no $variable in it).
#pragma once

#include <nori/object.h>

#include <any>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace nori {

class LoadAhead {
public:
    /// Reads and decodes the file at `path`: what a plugin's constructor would do with it.
    using Reader = std::function<std::any(const std::string &path)>;
    /// Who takes the reads of a file that several elements name.
    enum class Sharing {
        /// Each element takes a read of its own (a mesh moves the data into itself).
        PerElement,
        /// The file is read ahead once, for the first element that takes it: its plugins
        /// share what they make of it (the texture cache), or read it themselves.
        PerPath,
    };

    /// Registers the reader named `reader` (e.g. "ply").
    static void registerReader(const std::string &reader, Reader read,
                               Sharing sharing = Sharing::PerElement);
    /// Says that the plugin `pluginType` of class `classType` reads the file named by its
    /// `filename` with `reader`.
    static void registerPlugin(NoriObject::EClassType classType, const std::string &pluginType,
                               const std::string &reader);
    /// The reader of that plugin's file, or nullptr when it has none.
    static const std::string *readerOf(NoriObject::EClassType classType,
                                       const std::string &pluginType);

    /// Reads started on this thread go to up to maxParallelism() − 1 helper threads while
    /// this object lives (one scene load). Its destructor drops reads nobody took and waits
    /// for the ones running.
    LoadAhead();
    ~LoadAhead();
    LoadAhead(const LoadAhead &) = delete;
    LoadAhead &operator=(const LoadAhead &) = delete;

    /// Starts reading `path` for a later take(reader, path), in the order started; a
    /// PerPath reader's file only once.
    void start(const std::string &reader, const std::string &path);

    /// The result of a read of `path` by `reader` started on this thread and not yet
    /// taken: waits for it, or reads it here if no helper has begun. Rethrows what the
    /// reader threw. std::nullopt when no such read was started (no load ahead on this
    /// thread, or the parser could not tell the file).
    template <typename T>
    static std::optional<T> take(const std::string &reader, const std::string &path) {
        std::optional<std::any> result = takeAny(reader, path);
        if (!result)
            return std::nullopt;
        return std::any_cast<T>(std::move(*result));
    }

    /// take(reader, path) if the read was started, else read(path) here.
    template <typename T, typename Read>
    static T takeOrRead(const std::string &reader, const std::string &path, const Read &read) {
        std::optional<T> result = take<T>(reader, path);
        return result ? std::move(*result) : read(path);
    }

private:
    static std::optional<std::any> takeAny(const std::string &reader, const std::string &path);

    struct State;
    std::unique_ptr<State> m_state;
    LoadAhead *m_outer; ///< the load ahead this one hides on this thread (nested loads)
};

/// At start-up, registers the reader `name` (a function of the path to a std::any) with
/// its LoadAhead::Sharing. (The variables' names are made unique with __COUNTER__: a unity
/// build compiles several plugin files as one.)
#define NORI_REGISTER_READER(name, read, sharing)                                                  \
    const bool NORI_LOAD_AHEAD_NAME(readerRegistered, __COUNTER__) = [] {                          \
        ::nori::LoadAhead::registerReader(name, read, sharing);                                    \
        return true;                                                                               \
    }()
/// At start-up, beside NORI_REGISTER_CLASS(cls, type): the plugin reads its `filename`
/// with the reader `reader`, which the parser may start ahead of it.
#define NORI_REGISTER_LOAD_AHEAD(cls, type, reader)                                                \
    const bool NORI_LOAD_AHEAD_NAME(loadAheadRegistered, __COUNTER__) = [] {                       \
        ::nori::LoadAhead::registerPlugin(cls::kClassType, type, reader);                          \
        return true;                                                                               \
    }()
#define NORI_LOAD_AHEAD_NAME(prefix, counter) NORI_LOAD_AHEAD_PASTE(prefix, counter)
#define NORI_LOAD_AHEAD_PASTE(prefix, counter) prefix##counter

} // namespace nori
