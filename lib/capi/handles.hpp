// Live-handle bookkeeping for the C ABI. A handle is checked against the set
// of live handles of its kind before it is dereferenced, so NULL, foreign
// (wrong kind), destroyed and double-destroyed handles give a status instead
// of undefined behaviour.
#pragma once

namespace um::capi {

enum class HandleKind { context = 1, options = 2, triangulation = 3, spacing = 4,
                        features = 5, mesh = 6 };

void register_handle(const void *handle, HandleKind kind);
// Returns false when the handle was not live (so destroy is idempotent).
bool unregister_handle(const void *handle, HandleKind kind);
bool is_live(const void *handle, HandleKind kind);
const char *kind_name(HandleKind kind);

}  // namespace um::capi
