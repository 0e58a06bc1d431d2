#include "io/error_text.hpp"

#include <cerrno>

#include <netcdf.h>

#include "core/text.hpp"

namespace um::io {

std::string system_error_text(int error) {
    switch (error) {
        case ENOENT: return "no such file or directory";
        case EACCES: return "permission denied";
        case EPERM: return "operation not permitted";
        case EISDIR: return "is a directory";
        case ENOTDIR: return "a component of the path is not a directory";
        case ENAMETOOLONG: return "file name too long";
        case EMFILE:
        case ENFILE: return "too many open files";
        case ENOMEM: return "out of memory";
        case ENOSPC: return "no space left on device";
        case EDQUOT: return "disk quota exceeded";
        case EFBIG: return "file too large";
        case EROFS: return "read-only file system";
        case EIO: return "input/output error";
        case EXDEV: return "not on the same file system";
        default: return concat("system error ", error);
    }
}

std::string netcdf_status_text(int status) {
    return status > 0 ? system_error_text(status) : std::string(nc_strerror(status));
}

}  // namespace um::io
