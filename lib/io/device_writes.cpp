#include "io/device_writes.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <new>
#include <utility>

namespace um::io {

bool write_direct(int fd, uint64_t offset, const unsigned char *data, size_t n,
                  const DeviceWrites::Fallback &fallback) {
    while (n > 0) {
        const ssize_t wrote = ::pwrite(fd, data, n, static_cast<off_t>(offset));
        if (wrote < 0 && errno == EINTR) continue;
        if (wrote < 0 && errno == EINVAL) {  // O_DIRECT refused: the page cache takes them
            fallback(offset, data, n);
            return false;
        }
        if (wrote <= 0 || static_cast<size_t>(wrote) % DeviceWrites::kAlignment != 0) {
            // A partial block taken: the rest through the cache. Nothing
            // taken: the same bytes through the cache, whose error (a full
            // disk) names the file.
            const size_t done = wrote > 0 ? static_cast<size_t>(wrote) : 0;
            fallback(offset + done, data + done, n - done);
            return true;
        }
        data += wrote, offset += static_cast<uint64_t>(wrote), n -= static_cast<size_t>(wrote);
    }
    return true;
}

DeviceWrites::DeviceWrites(int fd, Fallback fallback)
    : fd_(fd), fallback_(std::move(fallback)), thread_([this] { run(); }) {}

DeviceWrites::~DeviceWrites() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    thread_.join();
}

DeviceWrites::Staging DeviceWrites::take(size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return failure_ || queued_bytes_ == 0 || queued_bytes_ + n <= kMaxQueuedBytes; });
    rethrow_failure_locked();
    // The smallest free buffer that holds n bytes without being more than
    // twice as large (so the queue's buffers stay within twice its bytes).
    auto best = free_.end();
    for (auto it = free_.begin(); it != free_.end(); ++it)
        if (it->capacity >= n && it->capacity / 2 <= n && (best == free_.end() || it->capacity < best->capacity))
            best = it;
    if (best != free_.end()) {
        Staging s = std::move(*best);
        free_.erase(best);
        return s;
    }
    lock.unlock();
    const size_t bytes = (n + kAlignment - 1) / kAlignment * kAlignment;
    void *memory = std::aligned_alloc(kAlignment, bytes);
    if (!memory) throw std::bad_alloc();
    Staging s;
    s.bytes = {static_cast<unsigned char *>(memory), std::free};
    s.capacity = bytes;
    return s;
}

void DeviceWrites::write(Staging buffer, uint64_t offset, size_t n) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        rethrow_failure_locked();
        queued_bytes_ += n;
        jobs_.push_back({std::move(buffer), offset, n});
    }
    changed_.notify_all();
}

void DeviceWrites::finish() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return failure_ || (jobs_.empty() && !busy_); });
    rethrow_failure_locked();
}

void DeviceWrites::rethrow_failure_locked() {
    if (failure_) std::rethrow_exception(failure_);
}

void DeviceWrites::run() {
    size_t since_sync = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        changed_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
        if (stopping_) return;
        Job job = std::move(jobs_.front());
        jobs_.pop_front();
        busy_ = true;
        const bool skip = static_cast<bool>(failure_);  // after a failure the file is abandoned
        lock.unlock();
        std::exception_ptr failed;
        if (!skip) {
            try {
                write_now(job);
            } catch (...) {
                failed = std::current_exception();
            }
            since_sync += job.n;
            // A hint, as ReplacingFile::start_writeback: an error it meets
            // is still reported to commit's fsync, on its own descriptor.
            if (since_sync >= kSyncBytes) (void)::fdatasync(fd_), since_sync = 0;
        }
        lock.lock();
        if (failed && !failure_) failure_ = failed;
        queued_bytes_ -= job.n;
        free_.push_back(std::move(job.buffer));
        if (free_.size() > kFreeBuffers) free_.erase(free_.begin());  // the longest unused
        busy_ = false;
        changed_.notify_all();
    }
}

void DeviceWrites::write_now(const Job &job) { write_direct(fd_, job.offset, job.buffer.data(), job.n, fallback_); }

}  // namespace um::io
