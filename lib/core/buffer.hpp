// A fixed-size array of trivial values that is not initialised when it is
// allocated, for the construction's large temporaries.
//
// Why: a std::vector writes every element once on allocation, on one
// thread, and that first write is what takes the page faults (about 2 us
// per 4 KiB page on the benchmark machine, 0.6 ms per MB). A Buffer is
// first written by the parallel loop that fills it, so the faults are
// spread over the threads, and a large one is aligned to 2 MiB and asks
// for transparent huge pages (core/huge_pages.hpp), five times cheaper to
// fault in there. Measured with bench_triangulation (tools/bench/HISTORY.md).
#pragma once

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>

#include "core/huge_pages.hpp"

namespace um {

template <class T>
class Buffer {
    static_assert(std::is_trivially_copyable<T>::value && std::is_trivially_destructible<T>::value,
                  "a Buffer holds plain values");
    static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__, "plain operator new must align T");

public:
    Buffer() = default;
    explicit Buffer(size_t size) : size_(size) {
        if (size == 0) return;
        if (size > size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        const size_t bytes = size * sizeof(T);
        if (bytes >= kHugePageMinBytes) {
            data_ = static_cast<T *>(allocate_huge_aligned(bytes));
            aligned_ = true;
            advise_huge_pages(data_, bytes);
        } else {
            data_ = static_cast<T *>(::operator new(bytes));
        }
    }
    // A Buffer over memory it does not own (nor free): `size` values at
    // `data`, which must outlive it.
    static Buffer over(T *data, size_t size) noexcept {
        Buffer b;
        b.data_ = data, b.size_ = size, b.owned_ = false;
        return b;
    }
    Buffer(Buffer &&other) noexcept { swap(other); }
    Buffer &operator=(Buffer &&other) noexcept {
        Buffer(std::move(other)).swap(*this);
        return *this;
    }
    Buffer(const Buffer &) = delete;
    Buffer &operator=(const Buffer &) = delete;
    ~Buffer() {
        if (!owned_)
            return;
        if (aligned_)
            free_huge_aligned(data_, size_ * sizeof(T));
        else
            ::operator delete(data_);
    }
    void swap(Buffer &other) noexcept {
        std::swap(data_, other.data_), std::swap(size_, other.size_), std::swap(aligned_, other.aligned_);
        std::swap(owned_, other.owned_);
    }

    size_t size() const { return size_; }
    T *data() { return data_; }
    const T *data() const { return data_; }
    T &operator[](size_t i) { return data_[i]; }
    const T &operator[](size_t i) const { return data_[i]; }
    T *begin() { return data_; }
    T *end() { return data_ + size_; }
    const T *begin() const { return data_; }
    const T *end() const { return data_ + size_; }

private:
    T *data_ = nullptr;
    size_t size_ = 0;
    bool aligned_ = false;
    bool owned_ = true;
};

}  // namespace um
