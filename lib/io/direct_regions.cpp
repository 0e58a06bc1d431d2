#include "io/direct_regions.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>
#include <system_error>

#include "core/error.hpp"
#include "io/error_text.hpp"

namespace um::io {

namespace {

uint64_t round_down(uint64_t x, uint64_t to) { return x / to * to; }
uint64_t round_up(uint64_t x, uint64_t to) { return (x + to - 1) / to * to; }

}  // namespace

DirectRegions::DirectRegions(const ReplacingFile &file, std::vector<uint64_t> begin, std::vector<uint64_t> end)
    : block_(std::max<uint64_t>(4096, static_cast<uint64_t>(std::max<long>(::sysconf(_SC_PAGESIZE), 0)))),
      file_(file), begin_(std::move(begin)), end_(std::move(end)), next_(begin_), carry_(begin_.size()) {
    if (end_.size() != begin_.size()) fail(UM_ERR_INTERNAL, "DirectRegions: ", begin_.size(), " begins, ", end_.size(), " ends");
#ifdef O_DIRECT
    fd_ = ::open(file.temporary_path().c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);  // -1: not here
#endif
}

DirectRegions::~DirectRegions() {
    device_.reset();  // its thread writes to fd_
    if (fd_ >= 0) ::close(fd_);
}

void DirectRegions::append(size_t r, uint64_t offset, const void *data, size_t n) {
    const unsigned char *p = static_cast<const unsigned char *>(data);
    uint64_t &at = next_[r];
    if (offset != at || at + n > end_[r])
        fail(UM_ERR_INTERNAL, "DirectRegions: bytes [", offset, ", ", offset + n, ") of region ", r, " [", begin_[r],
             ", ", end_[r], ") after byte ", at);
    // The whole blocks inside the region: [first, last).
    const uint64_t first = std::min(round_up(begin_[r], block_), end_[r]);
    const uint64_t last = std::max(round_down(end_[r], block_), first);
    auto through_cache = [&](size_t bytes) {  // the next `bytes` of p at `at`
        file_.write_at(at, p, bytes);
        at += bytes, p += bytes, n -= bytes;
    };
    if (fd_ < 0) return through_cache(n);
    if (at < first) through_cache(std::min<uint64_t>(n, first - at));
    if (n > 0 && at < last) {
        std::vector<unsigned char> &carry = carry_[r];
        const size_t take = static_cast<size_t>(std::min<uint64_t>(n, last - at));
        const size_t total = carry.size() + take, whole = static_cast<size_t>(round_down(total, block_));
        if (whole > 0) {  // the carry starts where the last whole block written ends
            write_whole_blocks(at - carry.size(), carry, p, whole);
            if (fd_ < 0) flush_carries_but(r);  // refused just now: the other regions' carries too
        }
        const size_t kept = total - whole;  // the new carry: the last `kept` bytes of carry + p[0, take)
        std::vector<unsigned char> rest(kept);
        for (size_t i = 0; i < kept; ++i) {
            const size_t k = total - kept + i;
            rest[i] = k < carry.size() ? carry[k] : p[k - carry.size()];
        }
        carry.swap(rest);
        at += take, p += take, n -= take;
        if (fd_ < 0 && !carry.empty()) {  // the file system refused: the carry goes through the cache
            file_.write_at(at - carry.size(), carry.data(), carry.size());
            carry.clear();
        }
    }
    if (n > 0) through_cache(n);
}

// The `whole` bytes of carry followed by p, at `offset`: on the device
// thread once there is one, in pieces of its buffers' size, else on this one.
void DirectRegions::write_whole_blocks(uint64_t offset, const std::vector<unsigned char> &carry,
                                       const unsigned char *p, size_t whole) {
    // Bytes [from, from + n) of carry followed by p, to `to`.
    auto fill = [&](unsigned char *to, size_t from, size_t n) {
        const size_t from_carry = from < carry.size() ? std::min(n, carry.size() - from) : 0;
        if (from_carry > 0) std::memcpy(to, carry.data() + from, from_carry);
        if (n > from_carry) std::memcpy(to + from_carry, p + (from + from_carry - carry.size()), n - from_carry);
    };
    if (device_) {
        for (size_t done = 0; done < whole; done += DeviceWrites::kPieceBytes) {
            const size_t n = std::min(whole - done, DeviceWrites::kPieceBytes);
            DeviceWrites::Staging staging = device_->take();
            fill(staging.get(), done, n);
            device_->write(std::move(staging), offset + done, n);
        }
        return;
    }
    if (staging_bytes_ < whole) {
        void *memory = std::aligned_alloc(block_, static_cast<size_t>(round_up(whole, block_)));
        if (!memory) throw std::bad_alloc();
        staging_ = {static_cast<unsigned char *>(memory), std::free};
        staging_bytes_ = whole;
    }
    fill(staging_.get(), 0, whole);
    if (!write_direct(fd_, offset, staging_.get(), whole, cache_fallback())) {  // refused: the cache from now on
        ::close(fd_);
        fd_ = -1;
        return;
    }
    if (no_thread_) return;
    try {
        device_ = std::make_unique<DeviceWrites>(fd_, cache_fallback());
        staging_.reset(), staging_bytes_ = 0;
    } catch (const std::system_error &) {  // no thread to be had: the writes stay on this one
        no_thread_ = true;
    }
}

DeviceWrites::Fallback DirectRegions::cache_fallback() const {
    return [&file = file_](uint64_t offset, const unsigned char *data, size_t n) { file.write_at(offset, data, n); };
}

void DirectRegions::flush_carries_but(size_t r) {
    for (size_t i = 0; i < carry_.size(); ++i)
        if (i != r && !carry_[i].empty()) {
            file_.write_at(next_[i] - carry_[i].size(), carry_[i].data(), carry_[i].size());
            carry_[i].clear();
        }
}

void DirectRegions::finish() {
    if (device_) device_->finish();
    for (size_t r = 0; r < begin_.size(); ++r)
        if (next_[r] != end_[r] || !carry_[r].empty())
            fail(UM_ERR_INTERNAL, "DirectRegions: region ", r, " [", begin_[r], ", ", end_[r], ") has bytes up to ",
                 next_[r], ", ", carry_[r].size(), " of them not written");
}

}  // namespace um::io
