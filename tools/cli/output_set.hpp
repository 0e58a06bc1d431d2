// The files of one `unimesh build` run, published as a set. Every file is
// written into a staging directory inside the output directory and moved
// into place (rename, so each file appears whole) only when all of them are
// written, manifest.json last: a failed or interrupted run leaves the files
// of the run before it as they were, and manifest.json names the run the
// files beside it belong to (mesh.nc's file_id and each file's size). An
// exclusive lock on the output directory keeps a second run from writing
// there at the same time. Creating the staging directory first also finds
// an output directory that cannot be written before any work is done.
#pragma once

#include <string>
#include <utility>
#include <vector>

class OutputSet {
public:
    // Creates out_dir if needed, takes its lock and makes the staging
    // directory; throws std::runtime_error with a one-line reason.
    explicit OutputSet(const std::string &out_dir);
    // Removes the staging directory (and what is left in it), and the output
    // directory's levels this run made when it published nothing; releases
    // the lock.
    ~OutputSet();
    OutputSet(const OutputSet &) = delete;
    OutputSet &operator=(const OutputSet &) = delete;

    // Where the run writes `name` until it is published.
    std::string staged(const std::string &name) const;
    const std::string &staging_directory() const { return staging_; }
    // Moves the staged files `names` into the output directory, removes the
    // earlier runs' files `not_written` (outputs this run did not make),
    // then writes manifest.json (the names, their sizes, `file_id`); throws
    // std::runtime_error naming the file that could not be moved.
    void publish(const std::vector<std::string> &names, const std::vector<std::string> &not_written,
                 const std::string &file_id);

private:
    static constexpr int kLockAttempts = 8;
    static int locked(const std::string &dir);
    void forget_made();

    std::string dir_, staging_;
    int lock_fd_ = -1;
    std::vector<std::string> made_;  // the levels of dir_ this run made, deepest first
    bool published_ = false;
};

// The file_id attribute of an MPAS mesh file ("" when it has none), which
// the manifest records.
std::string mesh_file_id(const std::string &mesh_nc);
