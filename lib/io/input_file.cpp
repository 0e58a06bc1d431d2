#include "io/input_file.hpp"

#include <sys/stat.h>

#include "core/error.hpp"

namespace um::io {

void require_regular_input(const std::string &path, const char *what) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return;
    if (S_ISDIR(st.st_mode)) fail(UM_ERR_IO, "cannot read ", what, " '", path, "': it is a directory");
    if (!S_ISREG(st.st_mode))
        fail(UM_ERR_IO, "cannot read ", what, " '", path, "': it is not a regular file (a device, FIFO or socket)");
}

}  // namespace um::io
