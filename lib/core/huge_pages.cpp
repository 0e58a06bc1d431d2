#include "core/huge_pages.hpp"

#include <cstdint>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define UM_HEAP_FOR_HUGE 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UM_HEAP_FOR_HUGE 1
#endif
#endif
#if !defined(__linux__)
#define UM_HEAP_FOR_HUGE 1
#endif

namespace um {

namespace {
#ifndef UM_HEAP_FOR_HUGE
size_t whole_pages(size_t bytes) {
    static const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    return (bytes + page - 1) / page * page;
}
#endif
}  // namespace

void *allocate_huge_aligned(size_t bytes) {
#ifdef UM_HEAP_FOR_HUGE
    return ::operator new(bytes, std::align_val_t(kHugePageBytes));
#else
    // Map a huge page more than needed, then give back what lies before the
    // first boundary and after the buffer's last page.
    const size_t used = whole_pages(bytes);
    if (used < bytes || used > size_t(-1) - kHugePageBytes) throw std::bad_alloc();
    const size_t mapped = used + kHugePageBytes;
    void *p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    const uintptr_t begin = reinterpret_cast<uintptr_t>(p);
    const uintptr_t aligned = (begin + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    if (aligned > begin) munmap(p, aligned - begin);
    const size_t after = mapped - (aligned - begin) - used;
    if (after > 0) munmap(reinterpret_cast<void *>(aligned + used), after);
    return reinterpret_cast<void *>(aligned);
#endif
}

void free_huge_aligned(void *data, size_t bytes) noexcept {
    if (!data) return;
#ifdef UM_HEAP_FOR_HUGE
    (void)bytes;
    ::operator delete(data, std::align_val_t(kHugePageBytes));
#else
    munmap(data, whole_pages(bytes));
#endif
}

void advise_huge_pages(const void *data, size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr size_t kHugePage = kHugePageBytes;
    if (!data || bytes < kHugePageMinBytes) return;
    const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHugePage - 1) / kHugePage * kHugePage;
    const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) / kHugePage * kHugePage;
    if (end > begin) madvise(reinterpret_cast<void *>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data, (void)bytes;
#endif
}

}  // namespace um
