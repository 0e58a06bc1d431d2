// std::vector whose resize(n) leaves new plain values unwritten.
//
// Why: the construction sizes its big arrays once and then fills every
// element in a parallel loop; a plain resize would first write them all on
// one thread, and that first write takes the page faults (0.6 ms per MB on
// the benchmark machine). Allocation is std::allocator's, so memory use is
// that of a std::vector. (Aligning its buffers of 2 MiB or more to huge
// pages raised the whole pipeline's peak from 243 to 293 bytes per cell at
// 671,000 cells, with no gain measured at 10^5 points.)
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

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

}  // namespace um
