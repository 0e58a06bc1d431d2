#include "capi/handles.hpp"

#include <mutex>
#include <unordered_map>

namespace um::capi {

namespace {
// Function-local statics: constructed on first use, no init call needed.
std::mutex &registry_mutex() {
    static std::mutex m;
    return m;
}
std::unordered_map<const void *, HandleKind> &registry() {
    static auto *r = new std::unordered_map<const void *, HandleKind>();  // never destroyed:
    return *r;  // handles may be destroyed from other static destructors
}
}  // namespace

void register_handle(const void *handle, HandleKind kind) {
    std::lock_guard<std::mutex> lock(registry_mutex());
    registry()[handle] = kind;
}

bool unregister_handle(const void *handle, HandleKind kind) {
    std::lock_guard<std::mutex> lock(registry_mutex());
    auto it = registry().find(handle);
    if (it == registry().end() || it->second != kind) return false;
    registry().erase(it);
    return true;
}

bool is_live(const void *handle, HandleKind kind) {
    if (!handle) return false;
    std::lock_guard<std::mutex> lock(registry_mutex());
    auto it = registry().find(handle);
    return it != registry().end() && it->second == kind;
}

const char *kind_name(HandleKind kind) {
    switch (kind) {
        case HandleKind::context: return "um_context";
        case HandleKind::options: return "um_options";
        case HandleKind::triangulation: return "um_triangulation";
        case HandleKind::spacing: return "um_spacing";
        case HandleKind::features: return "um_features";
        case HandleKind::mesh: return "um_mesh";
    }
    return "handle";
}

}  // namespace um::capi
