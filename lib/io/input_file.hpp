// Input files are read only when they are regular files: a FIFO would block
// the reader until some other process writes to it (for ever, from a
// mistaken path), and a device has no end; fopen also opens a directory on
// POSIX systems. A path that does not exist is left to the reader's own
// open, which names the error.
#pragma once

#include <string>

namespace um::io {

// Throws UM_ERR_IO "cannot read <what> '<path>': it is a directory" (or
// "... it is not a regular file (a device, FIFO or socket)").
void require_regular_input(const std::string &path, const char *what);

}  // namespace um::io
