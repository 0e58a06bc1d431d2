#include "output_set.hpp"

#include <netcdf.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "json_text.hpp"

namespace {

std::runtime_error failure(const std::string &what, int error) {
    return std::runtime_error(what + ": " + std::strerror(error));
}

void sync_directory(const std::string &dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

OutputSet::OutputSet(const std::string &out_dir) : dir_(out_dir.empty() ? "." : out_dir) {
    std::error_code ec;
    // The levels of dir_ this run makes, deepest first: a failed run removes them again.
    for (std::filesystem::path p = std::filesystem::absolute(dir_, ec); !ec && !p.empty() && !std::filesystem::exists(p, ec);
         p = p.parent_path()) {
        made_.push_back(p.string());
        if (p == p.parent_path()) break;
    }
    try {
        lock_fd_ = locked(dir_);
        staging_ = dir_ + "/.unimesh-staging-" + std::to_string(static_cast<long long>(::getpid()));
        std::filesystem::remove_all(staging_, ec);  // a dead run's with this pid
        if (::mkdir(staging_.c_str(), 0777) != 0) throw failure("--out " + dir_ + ": cannot write there", errno);
    } catch (...) {
        staging_.clear();
        forget_made();
        if (lock_fd_ >= 0) ::close(lock_fd_);
        lock_fd_ = -1;
        throw;
    }
}

// dir (made if needed) with its lock file locked. The lock file a failed
// run that made dir removes (forget_made) may be the one another run has
// opened: that one then finds its lock on a file no longer there, and
// takes the new one.
int OutputSet::locked(const std::string &dir) {
    const std::string lock = dir + "/.unimesh.lock";
    for (int attempt = 0;; ++attempt) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) throw std::runtime_error("--out " + dir + ": " + ec.message());
        if (!std::filesystem::is_directory(dir, ec)) throw std::runtime_error("--out " + dir + ": not a directory");
        const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
        if (fd < 0) {
            if (errno == ENOENT && attempt < kLockAttempts) continue;  // dir removed meanwhile
            throw failure("--out " + dir + ": cannot write there", errno);
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int error = errno;
            ::close(fd);
            if (error == EWOULDBLOCK) throw std::runtime_error("--out " + dir + ": another unimesh build is writing there");
            throw failure("--out " + dir + ": cannot lock it", error);
        }
        struct stat held {}, named {};
        if (::fstat(fd, &held) == 0 && ::stat(lock.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
            held.st_ino == named.st_ino)
            return fd;
        ::close(fd);
        if (attempt >= kLockAttempts) throw std::runtime_error("--out " + dir + ": cannot lock it (its lock file keeps changing)");
    }
}

// The lock file and the folders this run made (rmdir leaves any that hold
// something by now), while the lock is held.
void OutputSet::forget_made() {
    if (made_.empty() || lock_fd_ < 0) return;
    std::error_code ec;
    std::filesystem::remove(dir_ + "/.unimesh.lock", ec);
    for (const std::string &d : made_) ::rmdir(d.c_str());
}

OutputSet::~OutputSet() {
    std::error_code ec;
    if (!staging_.empty()) std::filesystem::remove_all(staging_, ec);
    if (!published_) forget_made();
    if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the lock
}

std::string OutputSet::staged(const std::string &name) const { return staging_ + "/" + name; }

void OutputSet::publish(const std::vector<std::string> &names, const std::vector<std::string> &not_written,
                        const std::string &file_id) {
    std::string manifest = "{\n  \"file_id\": \"" + json_escaped(file_id) + "\",\n  \"files\": [";
    for (size_t i = 0; i < names.size(); ++i) {
        std::error_code ec;
        const auto bytes = std::filesystem::file_size(staged(names[i]), ec);
        if (ec) throw std::runtime_error("cannot read " + staged(names[i]) + ": " + ec.message());
        manifest += std::string(i ? "," : "") + "\n    {\"name\": \"" + json_escaped(names[i]) +
                    "\", \"bytes\": " + std::to_string(bytes) + "}";
    }
    manifest += "\n  ]\n}\n";
    {
        std::ofstream out(staged("manifest.json"), std::ios::binary);
        out << manifest;
        out.flush();
        if (!out) throw std::runtime_error("cannot write " + staged("manifest.json"));
    }
    std::vector<std::string> all = names;
    all.push_back("manifest.json");  // last: it names the set
    for (const std::string &name : all) {
        const int fd = ::open(staged(name).c_str(), O_RDONLY | O_CLOEXEC);
        const bool synced = fd >= 0 && ::fsync(fd) == 0;
        if (fd >= 0) ::close(fd);
        if (!synced) throw failure("cannot write " + dir_ + "/" + name, errno);
    }
    sync_directory(staging_);
    // The old set's manifest goes first: while the files are being moved,
    // no manifest claims a mix of two runs.
    std::error_code ec;
    std::filesystem::remove(dir_ + "/manifest.json", ec);
    for (const std::string &name : not_written) std::filesystem::remove(dir_ + "/" + name, ec);
    for (const std::string &name : all)
        if (::rename(staged(name).c_str(), (dir_ + "/" + name).c_str()) != 0)
            throw failure("cannot move " + staged(name) + " to " + dir_ + "/" + name, errno);
    sync_directory(dir_);
    published_ = true;
}

std::string mesh_file_id(const std::string &mesh_nc) {
    int id = -1;
    std::string value;
    size_t length = 0;
    if (nc_open(mesh_nc.c_str(), NC_NOWRITE, &id) != NC_NOERR) return value;
    if (nc_inq_attlen(id, NC_GLOBAL, "file_id", &length) == NC_NOERR && length < 4096) {
        value.resize(length);
        if (nc_get_att_text(id, NC_GLOBAL, "file_id", value.data()) != NC_NOERR) value.clear();
    }
    nc_close(id);
    return value;
}
