#include <nori/loadahead.h>
#include <nori/parallel.h>

#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>
#include <vector>

namespace nori {

namespace {

struct RegisteredReader {
    LoadAhead::Reader read;
    LoadAhead::Sharing sharing;
};

std::map<std::string, RegisteredReader> &readers() {
    static std::map<std::string, RegisteredReader> table;
    return table;
}

/// The reader of each plugin that has one, by (class, plugin name).
std::map<std::pair<NoriObject::EClassType, std::string>, std::string> &pluginReaders() {
    static std::map<std::pair<NoriObject::EClassType, std::string>, std::string> table;
    return table;
}

/// The load ahead of the scene this thread is loading, if any.
thread_local LoadAhead *t_current = nullptr;

} // namespace

/// The reads, in the order started. Helpers take the oldest waiting one; a take() of one
/// that is still waiting reads it on the taking thread instead, so nothing waits for a
/// helper that has not begun.
struct LoadAhead::State {
    enum class Stage { Waiting, Reading, Done };
    struct Read {
        const Reader *read;
        std::string path;
        Stage stage = Stage::Waiting;
        std::any result;
        std::exception_ptr error;
    };

    std::mutex mutex;
    std::condition_variable changed; ///< a read was started or finished, or closing
    std::deque<Read> reads;          ///< stable addresses: a deque only grows at its end
    /// The reads not yet taken, by (reader, path); a file named twice has two, unless its
    /// reader shares it PerPath.
    std::multimap<std::pair<std::string, std::string>, Read *> untaken;
    /// The (reader, path) of every PerPath read started.
    std::set<std::pair<std::string, std::string>> startedPerPath;
    size_t nextWaiting = 0; ///< no read before this index is waiting
    bool closing = false;
    std::vector<std::thread> helpers;
    size_t helperLimit = 0;

    /// Reads `read` (its stage set to Reading by the caller, under the lock), then
    /// publishes the result.
    void run(Read &read, std::unique_lock<std::mutex> &lock) {
        lock.unlock();
        std::any result;
        std::exception_ptr error;
        try {
            result = (*read.read)(read.path);
        } catch (...) {
            error = std::current_exception();
        }
        lock.lock();
        read.result = std::move(result);
        read.error = error;
        read.stage = Stage::Done;
        changed.notify_all();
    }

    /// The oldest waiting read, or nullptr.
    Read *nextToRead() {
        while (nextWaiting < reads.size() && reads[nextWaiting].stage != Stage::Waiting)
            ++nextWaiting;
        return nextWaiting < reads.size() ? &reads[nextWaiting] : nullptr;
    }

    void helperLoop() {
        std::unique_lock<std::mutex> lock(mutex);
        while (true) {
            changed.wait(lock, [this] { return closing || nextToRead(); });
            if (closing)
                return;
            Read &read = *nextToRead();
            read.stage = Stage::Reading;
            run(read, lock);
        }
    }
};

void LoadAhead::registerReader(const std::string &reader, Reader read, Sharing sharing) {
    readers()[reader] = {std::move(read), sharing};
}

void LoadAhead::registerPlugin(NoriObject::EClassType classType, const std::string &pluginType,
                               const std::string &reader) {
    pluginReaders()[{classType, pluginType}] = reader;
}

const std::string *LoadAhead::readerOf(NoriObject::EClassType classType,
                                       const std::string &pluginType) {
    const auto found = pluginReaders().find({classType, pluginType});
    return found == pluginReaders().end() ? nullptr : &found->second;
}

LoadAhead::LoadAhead() : m_state(std::make_unique<State>()), m_outer(t_current) {
    m_state->helperLimit = static_cast<size_t>(std::max(0, maxParallelism() - 1));
    t_current = this;
}

LoadAhead::~LoadAhead() {
    t_current = m_outer;
    {
        std::lock_guard<std::mutex> lock(m_state->mutex);
        m_state->closing = true;
    }
    m_state->changed.notify_all();
    for (std::thread &helper : m_state->helpers)
        helper.join();
}

void LoadAhead::start(const std::string &reader, const std::string &path) {
    const auto registered = readers().find(reader);
    if (registered == readers().end())
        return;
    State &state = *m_state;
    {
        std::lock_guard<std::mutex> lock(state.mutex);
        if (registered->second.sharing == Sharing::PerPath &&
            !state.startedPerPath.emplace(reader, path).second)
            return;
        state.reads.push_back({&registered->second.read, path, State::Stage::Waiting, {}, nullptr});
        state.untaken.emplace(std::make_pair(reader, path), &state.reads.back());
    }
    // A helper for each read started, up to the limit: a scene of one mesh file starts one.
    // Without threads to spare (a limit of one, or none left), take() reads on its own.
    if (state.helpers.size() < state.helperLimit) {
        try {
            state.helpers.emplace_back([&state] { state.helperLoop(); });
        } catch (const std::system_error &) {
            state.helperLimit = state.helpers.size();
        }
    }
    // notify_all: takers wait on the same condition, and a notify_one could wake one of
    // them instead of the idle helper this read is for.
    state.changed.notify_all();
}

std::optional<std::any> LoadAhead::takeAny(const std::string &reader, const std::string &path) {
    if (!t_current)
        return std::nullopt;
    State &state = *t_current->m_state;
    std::unique_lock<std::mutex> lock(state.mutex);
    // The first started of a file named twice is the first taken (multimap keeps the order
    // of insertion among equal keys).
    const auto key = std::make_pair(reader, path);
    const auto entry = state.untaken.lower_bound(key);
    if (entry == state.untaken.end() || entry->first != key)
        return std::nullopt;
    State::Read *found = entry->second;
    state.untaken.erase(entry);
    if (found->stage == State::Stage::Waiting) {
        found->stage = State::Stage::Reading;
        state.run(*found, lock);
    }
    state.changed.wait(lock, [found] { return found->stage == State::Stage::Done; });
    if (found->error)
        std::rethrow_exception(found->error);
    return std::move(found->result);
}

} // namespace nori
