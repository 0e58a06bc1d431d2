// Direct (O_DIRECT) writes of whole 4 KiB blocks, done in order on a thread
// of their own. A direct write returns when the device has taken the bytes:
// on the thread that makes them (the MPAS writer, one of the threads making
// blocks of rows) each wait left a processor idle; and the flush before the
// file is renamed into place (ReplacingFile::commit) waits for the device's
// own part of every byte written, which grows with the file and came all at
// the end. Here the waits are on a thread that uses no processor while it
// waits, and it asks for a data sync every kSyncBytes, so that the device
// settles the file while the blocks are still being made. The caller's
// thread still copies the bytes into the buffers (and, for the MPAS file,
// swaps and hashes them). Measurements: tools/bench/HISTORY.md.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace um::io {

class DeviceWrites {
public:
    static constexpr size_t kAlignment = 4096;
    // Pieces of at most kPieceBytes, in at most kBuffers buffers of that
    // size, allocated as needed and used again: 32 MiB queued at most.
    static constexpr size_t kPieceBytes = size_t(8) << 20;
    static constexpr size_t kBuffers = 4;
    static constexpr size_t kSyncBytes = size_t(64) << 20;

    // kPieceBytes on huge pages (fewer page faults on their first touch),
    // aligned as O_DIRECT asks of the memory it reads.
    struct FreePiece {
        void operator()(unsigned char *p) const noexcept;
    };
    using Staging = std::unique_ptr<unsigned char, FreePiece>;
    // The same bytes written another way (through the page cache), for a
    // write the device refuses or takes in part; throws um::Error naming
    // the file when that fails too.
    using Fallback = std::function<void(uint64_t offset, const unsigned char *data, size_t n)>;

    // fd: open with O_DIRECT, for writing; it must outlive this object.
    DeviceWrites(int fd, Fallback fallback);
    // Abandons the writes not yet begun, after the one under way.
    ~DeviceWrites();
    DeviceWrites(const DeviceWrites &) = delete;
    DeviceWrites &operator=(const DeviceWrites &) = delete;

    // A buffer of kPieceBytes to fill and hand to write(); waits while all
    // kBuffers are queued. Rethrows the first failure of a write.
    Staging take();
    // Bytes [0, n) of `buffer` at `offset` of the file (n a multiple of
    // 4 KiB, at most kPieceBytes).
    void write(Staging buffer, uint64_t offset, size_t n);
    // Waits until every write handed over is done; rethrows the first
    // failure of one.
    void finish();

private:
    struct Job {
        Staging buffer;
        uint64_t offset;
        size_t n;
    };
    void run();
    void write_now(const Job &job);
    void rethrow_failure_locked();

    int fd_;
    Fallback fallback_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<Job> jobs_;
    std::vector<Staging> free_;  // buffers written, to be used again
    size_t allocated_ = 0;
    bool busy_ = false, stopping_ = false;
    std::exception_ptr failure_;
    std::thread thread_;  // started in the constructor's body, once the rest is in place
};

// Writes n bytes at `offset` with pwrite on the O_DIRECT descriptor fd;
// what it refuses or takes in part goes to `fallback`. Returns false when
// the file system refused O_DIRECT itself (EINVAL: fallback took them all).
bool write_direct(int fd, uint64_t offset, const unsigned char *data, size_t n,
                  const DeviceWrites::Fallback &fallback);

}  // namespace um::io
