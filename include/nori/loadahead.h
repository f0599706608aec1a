// Files read ahead: while the scene parser builds one object after another, helper
// threads already read and decode the files that later elements name (mesh files above
// all), so that a scene of hundreds of PLY files loads on every core.
//
// A plugin that reads a file in its constructor registers how (NORI_REGISTER_LOAD_AHEAD
// with its plugin name) and asks for the result by the path it would read
// (LoadAhead::take). The parser starts a read for every element of that plugin type whose
// `filename` it can resolve without running the plugin (no $variable in it).
#pragma once

#include <any>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace nori {

class LoadAhead {
public:
    /// Reads and decodes the file at `path`: what the plugin's constructor would do with it.
    using Reader = std::function<std::any(const std::string &path)>;

    /// Registers the reader of the plugin registered as `pluginType` (e.g. "ply").
    static void registerReader(const std::string &pluginType, Reader reader);
    /// Whether `pluginType` has a reader.
    static bool hasReader(const std::string &pluginType);

    /// Reads started on this thread go to up to maxParallelism() − 1 helper threads while
    /// this object lives (one scene load). Its destructor drops reads nobody took and waits
    /// for the ones running.
    LoadAhead();
    ~LoadAhead();
    LoadAhead(const LoadAhead &) = delete;
    LoadAhead &operator=(const LoadAhead &) = delete;

    /// Starts reading `path` for a later take(pluginType, path), in the order started.
    void start(const std::string &pluginType, const std::string &path);

    /// The result of a read of `path` started on this thread for `pluginType` and not yet
    /// taken: waits for it, or reads it here if no helper has begun. Rethrows what the
    /// reader threw. std::nullopt when no such read was started (no load ahead on this
    /// thread, or the parser could not tell the file).
    template <typename T>
    static std::optional<T> take(const std::string &pluginType, const std::string &path) {
        std::optional<std::any> result = takeAny(pluginType, path);
        if (!result)
            return std::nullopt;
        return std::any_cast<T>(std::move(*result));
    }

    /// take(pluginType, path) if the read was started, else read(path) here.
    template <typename T, typename Read>
    static T takeOrRead(const std::string &pluginType, const std::string &path, const Read &read) {
        std::optional<T> result = take<T>(pluginType, path);
        return result ? std::move(*result) : read(path);
    }

private:
    static std::optional<std::any> takeAny(const std::string &pluginType, const std::string &path);

    struct State;
    std::unique_ptr<State> m_state;
    LoadAhead *m_outer; ///< the load ahead this one hides on this thread (nested loads)
};

/// Registers `reader` for the plugin `type` at start-up, beside NORI_REGISTER_CLASS. (The
/// variable's name is made unique with __COUNTER__: a unity build compiles several plugin
/// files as one.)
#define NORI_REGISTER_LOAD_AHEAD(type, reader)                                                     \
    const bool NORI_LOAD_AHEAD_NAME(loadAheadRegistered, __COUNTER__) = [] {                       \
        ::nori::LoadAhead::registerReader(type, reader);                                           \
        return true;                                                                               \
    }()
#define NORI_LOAD_AHEAD_NAME(prefix, counter) NORI_LOAD_AHEAD_PASTE(prefix, counter)
#define NORI_LOAD_AHEAD_PASTE(prefix, counter) prefix##counter

} // namespace nori
