// What the first write to fresh memory costs on this machine, per MB, for
// the ways the triangulation can get its pages: 4 KiB pages faulted one by
// one, the same populated by the kernel in one call, and transparent huge
// pages (2 MiB, asked for with madvise as core/Buffer does). Each is
// measured on fresh memory of the given size, then written again (the cost
// of memory already in place).
//
// Why it exists: on a virtual machine the host may back the guest's memory
// only when first touched, so the same program's first run can be much
// slower than its next ones; bench_triangulation's children see that, and
// this shows it apart from any triangulation.
//
//   bench_first_touch [MB ...]        (default: 10 100 400)
#include <sys/mman.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

constexpr size_t kPage = 4096, kHugePage = size_t(2) << 20;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void touch(char *p, size_t bytes, char value) {
    for (size_t i = 0; i < bytes; i += kPage) p[i] = value;
}

enum class Way { fault_4k, populate_4k, huge_pages };

const char *name(Way way) {
    switch (way) {
    case Way::fault_4k: return "4 KiB pages, faulted";
    case Way::populate_4k: return "4 KiB pages, MAP_POPULATE";
    case Way::huge_pages: return "huge pages (madvise)";
    }
    return "";
}

// Returns false when the memory could not be had.
bool measure(Way way, size_t mb) {
    const size_t bytes = mb << 20, mapped = bytes + kHugePage;
    int flags = MAP_PRIVATE | MAP_ANONYMOUS;
    if (way == Way::populate_4k) flags |= MAP_POPULATE;
    const auto t0 = std::chrono::steady_clock::now();
    void *base = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, flags, -1, 0);
    if (base == MAP_FAILED) return false;
    char *p = static_cast<char *>(base);
    if (way == Way::huge_pages) {
        p = reinterpret_cast<char *>((reinterpret_cast<uintptr_t>(p) + kHugePage - 1) / kHugePage * kHugePage);
        madvise(p, bytes, MADV_HUGEPAGE);
    }
    if (way != Way::populate_4k) touch(p, bytes, 1);
    const double first = seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    touch(p, bytes, 2);
    const double again = seconds_since(t1);
    munmap(base, mapped);
    std::printf("%-28s %6zu MB   first touch %8.2f ms  %6.3f ms/MB   again %6.3f ms/MB\n", name(way),
                mb, 1e3 * first, 1e3 * first / double(mb), 1e3 * again / double(mb));
    return true;
}

}  // namespace

int main(int argc, char **argv) {
    std::vector<size_t> sizes;
    for (int i = 1; i < argc; ++i) {
        char *end = nullptr;
        const long mb = std::strtol(argv[i], &end, 10);
        if (!end || *end || mb <= 0) {
            std::fprintf(stderr, "bench_first_touch: size '%s' is not a positive number of MB\n", argv[i]);
            return 2;
        }
        sizes.push_back(static_cast<size_t>(mb));
    }
    if (sizes.empty()) sizes = {10, 100, 400};
    std::printf("# first write to fresh anonymous memory, one byte per 4 KiB; each size twice in a row\n");
    for (size_t mb : sizes)
        for (int round = 0; round < 2; ++round)
            for (Way way : {Way::huge_pages, Way::fault_4k, Way::populate_4k})
                if (!measure(way, mb)) {
                    std::fprintf(stderr, "bench_first_touch: no %zu MB to map\n", mb);
                    return 1;
                }
    return 0;
}
