#include "io/device_writes.hpp"

#include <unistd.h>

#include <cerrno>
#include <utility>

#include "core/error.hpp"
#include "core/huge_pages.hpp"

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

DeviceWrites::DeviceWrites(int fd, Fallback fallback) : fd_(fd), fallback_(std::move(fallback)) {
    free_.reserve(kBuffers);  // so that giving a buffer back never allocates (nor throws, on the thread)
    thread_ = std::thread([this] { run(); });
}

DeviceWrites::~DeviceWrites() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    thread_.join();
}

DeviceWrites::Staging DeviceWrites::take() {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return failure_ || !free_.empty() || allocated_ < kBuffers; });
    rethrow_failure_locked();
    if (!free_.empty()) {
        Staging s = std::move(free_.back());
        free_.pop_back();
        return s;
    }
    ++allocated_;
    lock.unlock();
    try {
        void *memory = allocate_huge_aligned(kPieceBytes);
        advise_huge_pages(memory, kPieceBytes);
        return Staging(static_cast<unsigned char *>(memory));
    } catch (...) {
        lock.lock();
        --allocated_;
        throw;
    }
}

void DeviceWrites::FreePiece::operator()(unsigned char *p) const noexcept { free_huge_aligned(p, kPieceBytes); }

void DeviceWrites::write(Staging buffer, uint64_t offset, size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    Job job{std::move(buffer), offset, n};
    // A buffer not queued goes back to the pool (take() counts on it).
    if (failure_ || n > kPieceBytes || n % kAlignment != 0) {
        free_.push_back(std::move(job.buffer));
        rethrow_failure_locked();
        fail(UM_ERR_INTERNAL, "DeviceWrites: a piece of ", n, " bytes");
    }
    try {
        jobs_.push_back(std::move(job));  // strong guarantee: job intact if it throws
    } catch (...) {
        free_.push_back(std::move(job.buffer));
        throw;
    }
    lock.unlock();
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
        free_.push_back(std::move(job.buffer));
        busy_ = false;
        changed_.notify_all();
    }
}

void DeviceWrites::write_now(const Job &job) { write_direct(fd_, job.offset, job.buffer.get(), job.n, fallback_); }

}  // namespace um::io
