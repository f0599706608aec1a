// std::allocator for the large arrays that incoherent rays read at random (BVH nodes,
// triangle packets): cache-line aligned, and from 2 MiB up aligned to 2 MiB and advised
// for transparent huge pages, so that tens of megabytes of tree cost a few TLB entries
// rather than thousands (Linux madvise(2), MADV_HUGEPAGE; Embree does the same).
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <new>

namespace nori {

template <typename T> struct LargeArrayAllocator {
    using value_type = T;
    static constexpr size_t kHugePage = size_t(2) << 20;

    LargeArrayAllocator() = default;
    template <typename U> LargeArrayAllocator(const LargeArrayAllocator<U> &) {}

    T *allocate(size_t n) {
        const size_t bytes = n * sizeof(T);
        if (bytes < kHugePage)
            return static_cast<T *>(::operator new(bytes, std::align_val_t(64)));
        // Whole huge pages; the advice is a hint, so its failure changes nothing.
        const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        void *memory = ::operator new(rounded, std::align_val_t(kHugePage));
        madvise(memory, rounded, MADV_HUGEPAGE);
        return static_cast<T *>(memory);
    }
    void deallocate(T *p, size_t n) {
        const bool huge = n * sizeof(T) >= kHugePage;
        ::operator delete(p, std::align_val_t(huge ? kHugePage : 64));
    }
    bool operator==(const LargeArrayAllocator &) const { return true; }
    bool operator!=(const LargeArrayAllocator &) const { return false; }
};

} // namespace nori
