// std::vector whose resize(n) leaves new plain values unwritten.
//
// Why: the construction sizes its big arrays once and then fills every
// element in a parallel loop; a plain resize would first write them all on
// one thread, and that first write takes the page faults (0.6 ms per MB on
// the benchmark machine). Allocation is std::allocator's, so memory use is
// that of a std::vector.
//
// HugePageVector: the same, but once reset_on_huge_pages() set it so, a
// buffer of 2 MiB or more starts on a 2 MiB boundary (allocate_huge_aligned:
// a mapping of its own, given back when freed), so that huge-page advice
// (core/huge_pages.hpp) covers all of it instead of the whole huge pages
// that happen to fall inside. For the triangulation's lifted points and
// triangles when a construction from many points sizes them once and
// advises them: at 10^5 points they are 2.4 and 4.8 MB, and unaligned only
// one huge page of the two was covered; aligned, a construction takes about
// 1,000 page faults fewer there (1,880 -> 862 on two threads) and up to 500
// fewer from 10^6 points on, in the same memory (bench_triangulation,
// tools/bench/HISTORY.md). Only there: the refinement's and optimisation's
// triangulations, which grow and are copied, keep heap memory (with every
// buffer of theirs of 2 MiB or more mapped so, the whole pipeline's peak rose
// from 243 to 282 bytes per cell on the uniform 30 km case, bench_refine:
// a fresh mapping cannot reuse the heap's freed pages).
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

template <class T>
struct UninitAllocator : std::allocator<T> {
    UninitAllocator() = default;
    template <class U>
    UninitAllocator(const UninitAllocator<U> &) noexcept {}
    template <class U>
    struct rebind {
        using other = UninitAllocator<U>;
    };
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
};

template <class T, class U>
bool operator==(const UninitAllocator<T> &, const UninitAllocator<U> &) noexcept {
    return true;
}
template <class T, class U>
bool operator!=(const UninitAllocator<T> &, const UninitAllocator<U> &) noexcept {
    return false;
}

template <class T>
using UninitVector = std::vector<T, UninitAllocator<T>>;

// HugePageVector's allocator: with `on_huge_pages`, buffers of 2 MiB or more
// come from allocate_huge_aligned. The setting belongs to the container: it
// moves and swaps with the buffer (which it freed as it allocated), and a
// copy starts without it, so that only the vectors a caller sets up so are
// placed so, and their copies are ordinary heap memory.
template <class T>
struct HugePageAllocator : UninitAllocator<T> {
    bool on_huge_pages = false;

    HugePageAllocator() = default;
    explicit HugePageAllocator(bool on) noexcept : on_huge_pages(on) {}
    template <class U>
    HugePageAllocator(const HugePageAllocator<U> &other) noexcept : on_huge_pages(other.on_huge_pages) {}
    template <class U>
    struct rebind {
        using other = HugePageAllocator<U>;
    };
    using propagate_on_container_move_assignment = std::true_type;
    using propagate_on_container_swap = std::true_type;
    using propagate_on_container_copy_assignment = std::false_type;
    using is_always_equal = std::false_type;
    HugePageAllocator select_on_container_copy_construction() const noexcept { return {}; }

    T *allocate(size_t n) {
        if (!huge(n)) return std::allocator<T>::allocate(n);
        return static_cast<T *>(allocate_huge_aligned(n * sizeof(T)));
    }
    void deallocate(T *p, size_t n) noexcept {
        if (!huge(n))
            std::allocator<T>::deallocate(p, n);
        else
            free_huge_aligned(p, n * sizeof(T));
    }

private:
    // (Counts too large for the bytes to be counted are left to
    // std::allocator, which throws.)
    bool huge(size_t n) const noexcept {
        return on_huge_pages && n <= size_t(-1) / sizeof(T) && n * sizeof(T) >= kHugePageMinBytes;
    }
};

template <class T, class U>
bool operator==(const HugePageAllocator<T> &a, const HugePageAllocator<U> &b) noexcept {
    return a.on_huge_pages == b.on_huge_pages;
}
template <class T, class U>
bool operator!=(const HugePageAllocator<T> &a, const HugePageAllocator<U> &b) noexcept {
    return !(a == b);
}

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

// Empties v and sets whether its buffers of 2 MiB or more start on a huge
// page, from its next allocation on.
template <class T>
void reset_on_huge_pages(HugePageVector<T> &v, bool on_huge_pages) {
    HugePageVector<T>(HugePageAllocator<T>(on_huge_pages)).swap(v);
}

// Empties v and sizes it to n values, unwritten, on huge pages when it fills
// one: advised before the first touch, which is what places the pages, so
// that the parallel loop that first writes it takes the page faults.
template <class T>
void size_on_huge_pages(HugePageVector<T> &v, size_t n) {
    reset_on_huge_pages(v, n * sizeof(T) >= kHugePageMinBytes);
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(T));
    v.resize(n);
}

}  // namespace um
