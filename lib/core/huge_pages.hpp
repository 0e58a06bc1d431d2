// Advice to back a large buffer with transparent huge pages (2 MiB).
//
// Why: building a triangulation of 10^6 points fills about 90 MB of fresh
// memory (triangles, lifted points): with 4 KiB pages that is some 23,000
// page faults, and the insertion's reads, which follow the mesh rather than
// memory, miss the TLB often. Linux hands huge pages only to regions that
// ask for them (madvise) on most distributions, Debian's included.
// Measured with bench_triangulation (tools/bench/HISTORY.md).
//
// Who asks: the construction from many points (its arrays are sized once,
// up front and exactly) and core/Buffer's temporaries of 2 MiB or more
// (sort keys, which the pipeline's spatial reordering uses too). Arrays
// that grow a little at a time, as in the refinement, would round each
// buffer up to whole huge pages for nothing.
#pragma once

#include <cstddef>

namespace um {

constexpr size_t kHugePageBytes = size_t(2) << 20;
// Advice is taken from one huge page on.
constexpr size_t kHugePageMinBytes = kHugePageBytes;

// Asks for huge pages over the whole 2 MiB pages inside [data, data + bytes),
// for buffers of kHugePageMinBytes or more. Advice only: no effect where
// the system has no transparent huge pages, and nothing to undo.
void advise_huge_pages(const void *data, size_t bytes) noexcept;

}  // namespace um
