// Version and status entry points: no handles, no state.
#include "capi/api.hpp"

extern "C" {

UM_API int32_t um_version_number(void) { return UM_VERSION_NUMBER; }

UM_API void um_version(int32_t *major, int32_t *minor, int32_t *patch) {
    if (major) *major = UM_VERSION_MAJOR;
    if (minor) *minor = UM_VERSION_MINOR;
    if (patch) *patch = UM_VERSION_PATCH;
}

UM_API const char *um_version_string(void) { return UM_VERSION_STRING; }

UM_API const char *um_status_string(um_status status) {
    switch (status) {
        case UM_OK: return "success";
        case UM_ERR_USAGE: return "usage error";
        case UM_ERR_NULL_ARGUMENT: return "a required pointer argument is NULL";
        case UM_ERR_INVALID_HANDLE: return "not a live handle of the expected kind";
        case UM_ERR_INVALID_ARGUMENT: return "invalid argument value";
        case UM_ERR_UNKNOWN_OPTION: return "unknown option";
        case UM_ERR_OPTION_TYPE: return "option set with the wrong type";
        case UM_ERR_BUFFER_TOO_SMALL: return "output buffer too small";
        case UM_ERR_WRONG_ORDER: return "call made in the wrong order";
        case UM_ERR_INPUT: return "invalid input data";
        case UM_ERR_NONFINITE_INPUT: return "NaN or infinite value in input data";
        case UM_ERR_COORDINATE_RANGE: return "coordinate out of range";
        case UM_ERR_DUPLICATE_POINTS: return "duplicate points";
        case UM_ERR_TOO_FEW_POINTS: return "too few distinct points";
        case UM_ERR_DEGENERATE_INPUT: return "degenerate input";
        case UM_ERR_NUMERICAL: return "numerical failure";
        case UM_ERR_OUT_OF_MEMORY: return "out of memory";
        case UM_ERR_MEMORY_CAP: return "request exceeds the memory cap";
        case UM_ERR_LIMIT: return "size limit exceeded";
        case UM_ERR_IO: return "input/output error";
        case UM_ERR_FILE_FORMAT: return "file format error";
        case UM_CANCELLED: return "cancelled by the progress callback";
        case UM_ERR_INTERNAL: return "internal error";
        default: return "unknown status";
    }
}

UM_API int32_t um_status_class(um_status status) {
    if (status < 0 || status > 999) return 900;
    return status / 100 * 100;
}

}  // extern "C"
