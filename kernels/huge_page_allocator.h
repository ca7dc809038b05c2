#pragma once
// The allocator of the arrays a traversal reads at random (BVH nodes, leaf blocks): an
// allocation of 2 MB or more is 2 MB aligned and marked MADV_HUGEPAGE before its first touch.
// Where Linux's transparent huge pages are set to "madvise" (Debian's default, and the bench
// machine's), the tree then sits on 2 MB pages: a random walk over the dragon's 52 MB tree
// otherwise misses the TLB at nearly every node, which made the dragon's shadow rays 3x
// slower than Embree's inside the renderer (Embree advises its own trees the same way).
// Smaller arrays, and systems without the advice, get plain aligned memory.
#include <cstddef>
#include <cstdlib>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace foton::kern {

inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) {}
    template <class U>
    bool operator==(const HugePageAllocator<U>&) const {
        return true;
    }
    template <class U>
    bool operator!=(const HugePageAllocator<U>&) const {
        return false;
    }

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const std::size_t bytes = n * sizeof(T);
        const bool huge = bytes >= kHugePageBytes;
        const std::size_t align = huge ? kHugePageBytes : (alignof(T) > 64 ? alignof(T) : 64);
        // aligned_alloc wants a multiple of the alignment.
        const std::size_t rounded = (bytes + align - 1) / align * align;
        void* p = std::aligned_alloc(align, rounded ? rounded : align);
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (huge) madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t) noexcept {
        std::free(p);
    }
};

}  // namespace foton::kern
