// std::vector whose resize(n) leaves new plain values unwritten.
//
// Why: the construction sizes its big arrays once and then fills every
// element in a parallel loop; a plain resize would first write them all on
// one thread, and that first write takes the page faults (0.6 ms per MB on
// the benchmark machine). Allocation is std::allocator's, so memory use is
// that of a std::vector. (Aligning all of them, 2 MiB or more, to huge
// pages raised the whole pipeline's peak from 243 to 293 bytes per cell at
// 671,000 cells, with no gain measured at 10^5 points.)
//
// HugePageVector: the same, but a buffer of 2 MiB or more starts on a
// 2 MiB boundary, so that huge-page advice (core/huge_pages.hpp) covers all
// of it instead of the whole huge pages that happen to fall inside. For the
// triangulation's lifted points and triangles, which a construction from
// many points sizes once and advises: at 10^5 points they are 2.4 and 4.8
// MB, and unaligned only one huge page of the two arrays was covered
// (bench_triangulation, tools/bench/HISTORY.md).
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/huge_pages.hpp"

namespace um {

// Whether UninitVector leaves new values of T unwritten: types whose default
// initialisation writes nothing (plain values without member initialisers),
// and types that opt in by specialising this beside the type (geom::Vec3,
// in geom/sphere.hpp: its `= 0` member initialisers would otherwise make
// resize() zero the triangulation's lifted points on one thread before the
// parallel gather writes them again). Opt-in, not every trivially copyable type: a member
// initialiser that matters (say `int32_t tri = kNone`) must not be skipped
// silently.
template <class T>
struct LeftUnwritten : std::is_trivially_default_constructible<T> {};

template <class T, bool kHugePageAligned = false>
struct UninitAllocator : std::allocator<T> {
    UninitAllocator() = default;
    template <class U>
    UninitAllocator(const UninitAllocator<U, kHugePageAligned> &) noexcept {}
    template <class U>
    struct rebind {
        using other = UninitAllocator<U, kHugePageAligned>;
    };
    T *allocate(size_t n) {
        if (!huge(n)) return std::allocator<T>::allocate(n);
        return static_cast<T *>(::operator new(n * sizeof(T), std::align_val_t(kHugePageBytes)));
    }
    void deallocate(T *p, size_t n) noexcept {
        if (!huge(n))
            std::allocator<T>::deallocate(p, n);
        else
            ::operator delete(p, std::align_val_t(kHugePageBytes));
    }
    // Leaves LeftUnwritten values unwritten where std::allocator would
    // value-initialise them (zero), and default-initialises the others.
    // (An opted-in type is trivially copyable and destructible: its values
    // need no constructor call to exist, the allocator's storage holds them
    // implicitly.)
    template <class U>
    void construct(U *p) noexcept(std::is_nothrow_default_constructible<U>::value) {
        if constexpr (LeftUnwritten<U>::value) {
            static_assert(std::is_trivially_copyable<U>::value && std::is_trivially_destructible<U>::value,
                          "only plain values may be left unwritten");
        } else {
            ::new (static_cast<void *>(p)) U;
        }
    }
    template <class U, class... Args>
    void construct(U *p, Args &&...args) {
        ::new (static_cast<void *>(p)) U(std::forward<Args>(args)...);
    }

private:
    // (Counts too large for the bytes to be counted are left to
    // std::allocator, which throws.)
    static bool huge(size_t n) noexcept {
        return kHugePageAligned && n <= size_t(-1) / sizeof(T) && n * sizeof(T) >= kHugePageMinBytes;
    }
};

template <class T, class U, bool A>
bool operator==(const UninitAllocator<T, A> &, const UninitAllocator<U, A> &) noexcept {
    return true;
}
template <class T, class U, bool A>
bool operator!=(const UninitAllocator<T, A> &, const UninitAllocator<U, A> &) noexcept {
    return false;
}

template <class T>
using UninitVector = std::vector<T, UninitAllocator<T>>;
template <class T>
using HugePageVector = std::vector<T, UninitAllocator<T, true>>;

}  // namespace um
