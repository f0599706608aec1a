// std::allocator for the large arrays that incoherent rays read at random (BVH nodes,
// triangle packets) and the BVH build's own: cache-line aligned, and with the whole 2 MiB
// ranges inside a large array advised for transparent huge pages, so that tens of
// megabytes of tree cost a few TLB entries rather than thousands, and a build takes far
// fewer page faults (Linux madvise(2), MADV_HUGEPAGE; Embree does the same). Only aligned
// 2 MiB ranges can be huge pages; the ends keep small pages, so the array costs no more
// memory than with std::allocator.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

namespace nori {

template <typename T> struct LargeArrayAllocator {
    using value_type = T;
    static constexpr size_t kHugePage = size_t(2) << 20;

    LargeArrayAllocator() = default;
    template <typename U> LargeArrayAllocator(const LargeArrayAllocator<U> &) {}

    T *allocate(size_t n) {
        void *memory = ::operator new(n * sizeof(T), std::align_val_t(64));
        // The whole 2 MiB ranges: from the first aligned address to the last aligned end.
        const size_t bytes = n * sizeof(T);
        const size_t misalignment = reinterpret_cast<uintptr_t>(memory) % kHugePage;
        const size_t lead = misalignment == 0 ? 0 : kHugePage - misalignment;
        // The advice is a hint: its failure changes nothing.
        if (bytes > lead && bytes - lead >= kHugePage)
            madvise(static_cast<char *>(memory) + lead, (bytes - lead) / kHugePage * kHugePage,
                    MADV_HUGEPAGE);
        return static_cast<T *>(memory);
    }
    void deallocate(T *p, size_t) { ::operator delete(p, std::align_val_t(64)); }
    /// Default-initialises where std::allocator value-initialises: resize() leaves
    /// trivial elements unwritten, for the parallel pass that fills them (a serial pass
    /// zeroing tens of megabytes first would take a tenth of a BVH build).
    template <typename U> void construct(U *p) noexcept(noexcept(U())) {
        ::new (static_cast<void *>(p)) U;
    }
    template <typename U, typename... Args> void construct(U *p, Args &&...args) {
        ::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
    }
    bool operator==(const LargeArrayAllocator &) const { return true; }
    bool operator!=(const LargeArrayAllocator &) const { return false; }
};

} // namespace nori
