// Regions of a file being written, each front to back in pieces (an MPAS
// variable's values, a block of rows at a time), around the page cache: the
// whole 4 KiB blocks inside a region go to the device with O_DIRECT, from
// buffers of our own, and the partial blocks at its two ends through the
// page cache. A file of gigabytes written through the page cache costs the
// writing thread the allocation of a fresh cache page for every 4 KiB and
// the copy into it (a quarter of the MPAS stage's processor time at 10 km,
// beside the threads making the next block), fills the cache with pages
// nobody reads and leaves them all for the final flush. Written directly,
// the first whole blocks on the caller's thread (the file system's answer
// to O_DIRECT), the rest on a thread of their own (device_writes.hpp),
// whose waits for the device use no processor. File systems without
// O_DIRECT (tmpfs, some network and FUSE ones) refuse it when the file is
// opened or at the first write; the writes then go through the page cache.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/device_writes.hpp"
#include "io/replacing_file.hpp"

namespace um::io {

class DirectRegions {
public:
    // Region r is [begin[r], end[r]) of the file that `file` is writing
    // (its temporary name is opened a second time, for O_DIRECT).
    DirectRegions(const ReplacingFile &file, std::vector<uint64_t> begin, std::vector<uint64_t> end);
    ~DirectRegions();
    DirectRegions(const DirectRegions &) = delete;
    DirectRegions &operator=(const DirectRegions &) = delete;

    // n bytes at `offset` of region r, where its last ones ended (the
    // region's begin at first). Throws UM_ERR_IO naming the file (a write
    // that failed), UM_ERR_INTERNAL for bytes out of order, bad_alloc.
    void append(size_t r, uint64_t offset, const void *data, size_t n);
    // Waits for the writes under way; throws what one of them met (UM_ERR_IO
    // naming the file), UM_ERR_INTERNAL unless every region was written to
    // its end.
    void finish();

private:
    // The unit of the direct writes: 4 KiB, or the page size where larger,
    // so that no page the cache holds (a region's ends, written through it
    // on the caller's thread) shares bytes with a direct write on the
    // device thread.
    const uint64_t block_;
    void write_whole_blocks(uint64_t offset, const std::vector<unsigned char> &carry, const unsigned char *p,
                            size_t whole);
    DeviceWrites::Fallback cache_fallback() const;
    // After O_DIRECT was refused: the carries of every region but r through the cache.
    void flush_carries_but(size_t r);

    const ReplacingFile &file_;
    std::vector<uint64_t> begin_, end_, next_;
    // Per region, the bytes past its last whole block written (fewer than block_).
    std::vector<std::vector<unsigned char>> carry_;
    // Until the device thread starts: 4 KiB-aligned, as O_DIRECT asks of
    // the memory it reads.
    std::unique_ptr<unsigned char, void (*)(void *)> staging_{nullptr, nullptr};
    size_t staging_bytes_ = 0;
    int fd_ = -1;
    // Once the first direct write went through: the writes after it.
    std::unique_ptr<DeviceWrites> device_;
    bool no_thread_ = false;  // the system gave none: not asked again
};

}  // namespace um::io
