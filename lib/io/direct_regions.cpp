#include "io/direct_regions.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>

#include "core/error.hpp"
#include "io/error_text.hpp"

namespace um::io {

namespace {

uint64_t round_down(uint64_t x, uint64_t to) { return x / to * to; }
uint64_t round_up(uint64_t x, uint64_t to) { return (x + to - 1) / to * to; }

}  // namespace

DirectRegions::DirectRegions(const ReplacingFile &file, std::vector<uint64_t> begin, std::vector<uint64_t> end)
    : file_(file), begin_(std::move(begin)), end_(std::move(end)), next_(begin_), carry_(begin_.size()) {
    if (end_.size() != begin_.size()) fail(UM_ERR_INTERNAL, "DirectRegions: ", begin_.size(), " begins, ", end_.size(), " ends");
#ifdef O_DIRECT
    fd_ = ::open(file.temporary_path().c_str(), O_WRONLY | O_DIRECT | O_CLOEXEC);  // -1: not here
#endif
}

DirectRegions::~DirectRegions() {
    if (fd_ >= 0) ::close(fd_);
}

void DirectRegions::append(size_t r, uint64_t offset, const void *data, size_t n) {
    const unsigned char *p = static_cast<const unsigned char *>(data);
    uint64_t &at = next_[r];
    if (offset != at || at + n > end_[r])
        fail(UM_ERR_INTERNAL, "DirectRegions: bytes [", offset, ", ", offset + n, ") of region ", r, " [", begin_[r],
             ", ", end_[r], ") after byte ", at);
    // The whole blocks inside the region: [first, last).
    const uint64_t first = std::min(round_up(begin_[r], kBlock), end_[r]);
    const uint64_t last = std::max(round_down(end_[r], kBlock), first);
    auto through_cache = [&](size_t bytes) {  // the next `bytes` of p at `at`
        file_.write_at(at, p, bytes);
        at += bytes, p += bytes, n -= bytes;
    };
    if (fd_ < 0) return through_cache(n);
    if (at < first) through_cache(std::min<uint64_t>(n, first - at));
    if (n > 0 && at < last) {
        std::vector<unsigned char> &carry = carry_[r];
        const size_t take = static_cast<size_t>(std::min<uint64_t>(n, last - at));
        const size_t total = carry.size() + take, whole = static_cast<size_t>(round_down(total, kBlock));
        if (whole > 0) {  // the carry starts where the last whole block written ends
            if (staging_bytes_ < whole) {
                void *memory = std::aligned_alloc(kBlock, whole);
                if (!memory) throw std::bad_alloc();
                staging_ = {static_cast<unsigned char *>(memory), std::free};
                staging_bytes_ = whole;
            }
            if (!carry.empty()) std::memcpy(staging_.get(), carry.data(), carry.size());
            std::memcpy(staging_.get() + carry.size(), p, whole - carry.size());
            write_whole_blocks(at - carry.size(), staging_.get(), whole);
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

void DirectRegions::write_whole_blocks(uint64_t offset, const unsigned char *data, size_t n) {
    while (n > 0) {
        const ssize_t wrote = ::pwrite(fd_, data, n, static_cast<off_t>(offset));
        if (wrote < 0 && errno == EINTR) continue;
        if (wrote < 0 && errno == EINVAL) {  // O_DIRECT refused at the first write: the cache, from now on
            ::close(fd_);
            fd_ = -1;
            file_.write_at(offset, data, n);
            return;
        }
        if (wrote <= 0 || static_cast<size_t>(wrote) % kBlock != 0) {
            if (wrote > 0) {  // a partial block written: the rest through the cache
                file_.write_at(offset + static_cast<uint64_t>(wrote), data + wrote, n - static_cast<size_t>(wrote));
                return;
            }
            file_.write_at(offset, data, n);  // the same bytes through the cache: its error (a full disk) names the file
            return;
        }
        data += wrote, offset += static_cast<uint64_t>(wrote), n -= static_cast<size_t>(wrote);
    }
}

void DirectRegions::flush_carries_but(size_t r) {
    for (size_t i = 0; i < carry_.size(); ++i)
        if (i != r && !carry_[i].empty()) {
            file_.write_at(next_[i] - carry_[i].size(), carry_[i].data(), carry_[i].size());
            carry_[i].clear();
        }
}

void DirectRegions::check_complete() const {
    for (size_t r = 0; r < begin_.size(); ++r)
        if (next_[r] != end_[r] || !carry_[r].empty())
            fail(UM_ERR_INTERNAL, "DirectRegions: region ", r, " [", begin_[r], ", ", end_[r], ") has bytes up to ",
                 next_[r], ", ", carry_[r].size(), " of them not written");
}

}  // namespace um::io
