// std::allocator for the large arrays that incoherent rays read at random (BVH nodes,
// triangle packets): cache-line aligned, and with the whole 2 MiB ranges inside a large
// array advised for transparent huge pages, so that tens of megabytes of tree cost a few
// TLB entries rather than thousands (Linux madvise(2), MADV_HUGEPAGE; Embree does the
// same). Only aligned 2 MiB ranges can be huge pages; the ends keep small pages, so the
// array costs no more memory than with std::allocator.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <new>

namespace nori {

template <typename T> struct LargeArrayAllocator {
    using value_type = T;
    static constexpr uintptr_t kHugePage = uintptr_t(2) << 20;

    LargeArrayAllocator() = default;
    template <typename U> LargeArrayAllocator(const LargeArrayAllocator<U> &) {}

    T *allocate(size_t n) {
        void *memory = ::operator new(n * sizeof(T), std::align_val_t(64));
        const auto start = reinterpret_cast<uintptr_t>(memory);
        const uintptr_t first = (start + kHugePage - 1) & ~(kHugePage - 1);
        const uintptr_t last = (start + n * sizeof(T)) & ~(kHugePage - 1);
        // The advice is a hint: its failure changes nothing.
        if (last > first)
            madvise(reinterpret_cast<void *>(first), last - first, MADV_HUGEPAGE);
        return static_cast<T *>(memory);
    }
    void deallocate(T *p, size_t) { ::operator delete(p, std::align_val_t(64)); }
    bool operator==(const LargeArrayAllocator &) const { return true; }
    bool operator!=(const LargeArrayAllocator &) const { return false; }
};

} // namespace nori
