#pragma once
// Private: an allocator for the large read-only arrays of the query structures (sample rows,
// ball tree points and nodes). Random queries touch a few blocks of each all over the array;
// with 4 KiB pages nearly every block is a TLB miss (a page walk). Arrays of 2 MiB or more are
// placed on 2 MiB boundaries and marked for transparent huge pages (madvise; a hint the kernel
// may ignore, with no effect on results).

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace taskmap {
namespace detail {

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) {}  // NOLINT: allocator conversion

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) {
      return static_cast<T*>(
          ::operator new(bytes, std::align_val_t(alignof(T) < 64 ? 64 : alignof(T))));
    }
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) {
      ::operator delete(p, std::align_val_t(alignof(T) < 64 ? 64 : alignof(T)));
    } else {
      std::free(p);
    }
  }
  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }
};

/// A vector on huge pages when large.
template <typename T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace detail
}  // namespace taskmap
