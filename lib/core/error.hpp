// The engine's one error type. Engine code throws um::Error; lib/capi turns it
// (and std::bad_alloc, and anything else) into a um_status at the C ABI.
#pragma once

#include <stdexcept>
#include <string>

#include "unimesh.h"
#include "core/text.hpp"

namespace um {

class Error : public std::runtime_error {
public:
    Error(um_status status, const std::string &message)
        : std::runtime_error(message), status_(status) {}
    um_status status() const noexcept { return status_; }

private:
    um_status status_;
};

// Throws um::Error with a message assembled from the arguments, e.g.
//   fail(UM_ERR_INVALID_ARGUMENT, "n_threads = ", n, " is out of range [0, 1024]");
template <class... Parts>
[[noreturn]] void fail(um_status status, const Parts &...parts) {
    throw Error(status, concat(parts...));
}

}  // namespace um
