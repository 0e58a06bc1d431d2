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

// `bytes` (> 0) of memory starting on a 2 MiB boundary, so that the advice
// above covers all of it; throws std::bad_alloc. Freed by
// free_huge_aligned with the same `bytes`. For core/Buffer's large
// temporaries and the arrays of a construction from many points
// (HugePageVector).
// On Linux these are mappings of their own (mmap), given back whole when
// freed. Aligned requests to glibc's heap - which serves large ones once
// its mmap threshold has risen, as it does after the first large free -
// leave up to 2 MiB of slack beside each, which other requests then reuse
// and keep resident: with the triangulation's arrays there, the whole
// pipeline's peak rose from 306 to 357 bytes per cell on coast-rivers-60km
// (bench_refine); with mappings it was 290. (AddressSanitizer builds use
// the heap, which it guards.)
void *allocate_huge_aligned(size_t bytes);
void free_huge_aligned(void *data, size_t bytes) noexcept;

}  // namespace um
