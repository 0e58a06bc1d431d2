#include "io/netcdf_lock.hpp"

namespace um::io {

// A function-local static: built on first use, so there is no init call.
// Never destroyed, so a file closed from a static destructor still finds it.
std::mutex &netcdf_mutex() {
    static auto *mutex = new std::mutex();
    return *mutex;
}

}  // namespace um::io
