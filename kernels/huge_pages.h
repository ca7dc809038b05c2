#pragma once
// An allocator for the big read-mostly arrays of the kernels (BVH nodes and triangle blocks).
// A tree over a million triangles spans tens of megabytes; with 4 KiB pages nearly every node
// a ray visits also misses the TLB. Arrays of 2 MiB and more are therefore aligned to 2 MiB
// and advised to the kernel as huge-page candidates (Linux transparent huge pages in "madvise"
// mode, the Debian default, only back memory that asks). Embree's allocator does the same.
#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace foton::kern {

inline constexpr std::size_t kHugePage = std::size_t(2) << 20;

template <class T>
struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        const bool huge = bytes >= kHugePage;
        const std::size_t align = huge ? kHugePage : (alignof(T) > 64 ? alignof(T) : 64);
        const std::size_t size = (bytes + align - 1) / align * align;
        void* p = std::aligned_alloc(align, size == 0 ? align : size);
        if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (huge) madvise(p, size, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t) { std::free(p); }

    template <class U>
    bool operator==(const HugePageAllocator<U>&) const {
        return true;
    }
};

template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace foton::kern
