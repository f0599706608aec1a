// The renderer's parallel loops, all in one place: oneTBB's work-stealing loops, or, in a
// ThreadSanitizer build, the same loops as a plain fork and join on std::threads.
//
// Why two: Debian's libtbb is not instrumented, so ThreadSanitizer does not see how its
// scheduler hands a task from one thread to another, nor how it recycles task objects
// between threads, and reports races on oneTBB's own objects and on everything a task
// touches (a test program of parallel_for, parallel_reduce and parallel_invoke: 28 false
// reports in 20 rounds, 2026-12-06). std::thread's creation and join are what TSan models
// exactly, so under TSan the loops below run their bodies on threads of their own, and TSan
// checks every access our bodies make, with the same happens-before edges oneTBB gives
// (the loop's start before every body, every body before the loop's end).
#pragma once

#include <algorithm>
#include <cstddef>

#if defined(__SANITIZE_THREAD__)
#define NORI_PARALLEL_FORK_JOIN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define NORI_PARALLEL_FORK_JOIN 1
#endif
#endif

#ifdef NORI_PARALLEL_FORK_JOIN
#include <atomic>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#endif

namespace nori {

#ifdef NORI_PARALLEL_FORK_JOIN
namespace detail {

/// The limit of the innermost ThreadLimit::run on this thread (0: the hardware's).
inline thread_local int t_threadLimit = 0;
/// Helper threads alive in all loops: a nested loop (the BVH's recursive build) runs on
/// its own thread once there are four per core.
inline std::atomic<int> g_helperThreads{0};

inline int hardwareThreads() {
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

inline int threadLimit() {
    return t_threadLimit > 0 ? t_threadLimit : hardwareThreads();
}

/// Calls task(i) for i in [0, count) on this thread and up to threadLimit() − 1 helpers;
/// after a task throws no other starts, and the first exception is rethrown after the join.
template <typename Task> void forkJoin(size_t count, const Task &task) {
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::mutex errorMutex;
    auto work = [&] {
        for (size_t i = next++; i < count && !failed; i = next++) {
            try {
                task(i);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(errorMutex);
                if (!error)
                    error = std::current_exception();
                failed = true;
            }
        }
    };
    const int limit = threadLimit();
    const size_t helpersWanted = std::min(count, static_cast<size_t>(limit)) - 1;
    std::vector<std::thread> helpers;
    for (size_t h = 0; h < helpersWanted; ++h) {
        if (g_helperThreads.fetch_add(1) >= 4 * hardwareThreads()) {
            --g_helperThreads;
            break;
        }
        try {
            helpers.emplace_back([&work, limit] {
                t_threadLimit = limit;
                work();
                --g_helperThreads;
            });
        } catch (const std::system_error &) { // no more threads: this one does the rest
            --g_helperThreads;
            break;
        }
    }
    work();
    for (std::thread &helper : helpers)
        helper.join();
    if (error)
        std::rethrow_exception(error);
}

/// [begin, end) cut into at most four chunks per thread of at least `grain` indices each;
/// calls chunk(k, first, last) for each, in parallel.
template <typename Index, typename Chunk>
void forChunks(Index begin, Index end, size_t grain, const Chunk &chunk) {
    const size_t size = static_cast<size_t>(end - begin);
    if (size == 0)
        return;
    const size_t wanted = 4 * static_cast<size_t>(threadLimit());
    const size_t count = std::max<size_t>(1, std::min(wanted, size / std::max<size_t>(1, grain)));
    auto at = [&](size_t offset) {
        return static_cast<Index>(begin + static_cast<std::ptrdiff_t>(offset));
    };
    forkJoin(count, [&](size_t k) { chunk(k, at(size * k / count), at(size * (k + 1) / count)); });
}

} // namespace detail
#endif

/// Calls body(i) for every i in [begin, end), in parallel.
template <typename Index, typename Body>
void parallelFor(Index begin, Index end, const Body &body) {
#ifdef NORI_PARALLEL_FORK_JOIN
    detail::forChunks(begin, end, 1, [&](size_t, Index first, Index last) {
        for (Index i = first; i != last; ++i)
            body(i);
    });
#else
    tbb::parallel_for(begin, end, body);
#endif
}

/// Calls body(i) for every i in [begin, end), in parallel, each i a task of its own: for
/// few, long and uneven steps (the render's image blocks).
template <typename Index, typename Body>
void parallelForEach(Index begin, Index end, const Body &body) {
#ifdef NORI_PARALLEL_FORK_JOIN
    detail::forkJoin(static_cast<size_t>(end - begin), [&](size_t k) {
        body(static_cast<Index>(begin + static_cast<std::ptrdiff_t>(k)));
    });
#else
    tbb::parallel_for(
        tbb::blocked_range<Index>(begin, end, 1),
        [&](const tbb::blocked_range<Index> &range) {
            for (Index i = range.begin(); i != range.end(); ++i)
                body(i);
        },
        tbb::simple_partitioner());
#endif
}

/// Calls body(first, last) on chunks of [begin, end) of at least `grain` indices (or
/// pointers), in parallel: for loops whose single steps are too small to schedule.
template <typename Index, typename Body>
void parallelForChunks(Index begin, Index end, size_t grain, const Body &body) {
#ifdef NORI_PARALLEL_FORK_JOIN
    detail::forChunks(begin, end, grain,
                      [&](size_t, Index first, Index last) { body(first, last); });
#else
    tbb::parallel_for(
        tbb::blocked_range<Index>(begin, end, grain),
        [&](const tbb::blocked_range<Index> &range) { body(range.begin(), range.end()); });
#endif
}

/// The reduction of [begin, end): every chunk of at least `grain` indices (or pointers)
/// folded by body(first, last, partial) → partial from `identity`, and the chunks' results
/// by combine(a, b) → a + b. combine must be associative; the grouping is not fixed.
template <typename Value, typename Index, typename Body, typename Combine>
Value parallelReduce(Index begin, Index end, size_t grain, const Value &identity, const Body &body,
                     const Combine &combine) {
#ifdef NORI_PARALLEL_FORK_JOIN
    std::vector<Value> partials(4 * static_cast<size_t>(detail::threadLimit()), identity);
    detail::forChunks(begin, end, grain, [&](size_t k, Index first, Index last) {
        partials[k] = body(first, last, identity);
    });
    Value result = identity;
    for (const Value &partial : partials)
        result = combine(result, partial);
    return result;
#else
    return tbb::parallel_reduce(
        tbb::blocked_range<Index>(begin, end, grain), identity,
        [&](const tbb::blocked_range<Index> &range, const Value &partial) {
            return body(range.begin(), range.end(), partial);
        },
        combine);
#endif
}

/// Calls first() and second() in parallel.
template <typename First, typename Second>
void parallelInvoke(const First &first, const Second &second) {
#ifdef NORI_PARALLEL_FORK_JOIN
    detail::forkJoin(2, [&](size_t k) { k == 0 ? first() : second(); });
#else
    tbb::parallel_invoke(first, second);
#endif
}

/// The number of threads the loops started here use at most.
inline int maxParallelism() {
#ifdef NORI_PARALLEL_FORK_JOIN
    return detail::threadLimit();
#else
    return tbb::this_task_arena::max_concurrency();
#endif
}

/// Runs f() so that this thread, while it waits for f's loops, takes no task from outside
/// them (oneTBB's isolation: a thread holding a lock must not start a task that waits
/// for the same lock). A thread of its own, as in the fork-join build, waits for nothing
/// else.
template <typename F> void runIsolated(const F &f) {
#ifdef NORI_PARALLEL_FORK_JOIN
    f();
#else
    tbb::this_task_arena::isolate(f);
#endif
}

/// At most `threads` threads (0: every core) for the loops started inside run().
#ifdef NORI_PARALLEL_FORK_JOIN
class ThreadLimit {
public:
    explicit ThreadLimit(int threads) : m_threads(threads) {}

    template <typename F> void run(const F &f) {
        const int outer = detail::t_threadLimit;
        detail::t_threadLimit = m_threads;
        try {
            f();
        } catch (...) {
            detail::t_threadLimit = outer;
            throw;
        }
        detail::t_threadLimit = outer;
    }

private:
    int m_threads;
};
#else
class ThreadLimit {
public:
    explicit ThreadLimit(int threads)
        : m_arena(threads > 0 ? threads : tbb::task_arena::automatic) {}

    template <typename F> void run(const F &f) { m_arena.execute(f); }

private:
    tbb::task_arena m_arena;
};
#endif

} // namespace nori
