#include "io/graph_info.hpp"

#include <cstdio>
#include <memory>

#include "core/error.hpp"
#include "io/replacing_file.hpp"

namespace um::io {

void write_graph_info(const dual::MpasMesh &m, const std::string &path) {
    ReplacingFile file(path, "graph.info file");
    {
        std::unique_ptr<std::FILE, int (*)(std::FILE *)> out(std::fopen(file.temporary_path().c_str(), "w"),
                                                              std::fclose);
        if (!out) fail(UM_ERR_IO, "cannot write graph.info file '", path, "'");
        int64_t pairs = 0;
        for (int64_t e = 0; e < m.n_edges; ++e) pairs += m.cells_on_edge[2 * e + 1] != dual::kNone;
        bool ok = std::fprintf(out.get(), "%lld %lld\n", static_cast<long long>(m.n_cells),
                               static_cast<long long>(pairs)) > 0;
        const size_t w = static_cast<size_t>(m.max_edges);
        for (size_t c = 0; ok && c < static_cast<size_t>(m.n_cells); ++c) {
            const char *separator = "";
            for (int32_t j = 0; j < m.n_edges_on_cell[c]; ++j) {
                const int32_t other = m.cells_on_cell[c * w + j];
                if (other == dual::kNone) continue;
                ok = ok && std::fprintf(out.get(), "%s%d", separator, other + 1) > 0;
                separator = " ";
            }
            ok = ok && std::fputc('\n', out.get()) != EOF;
        }
        ok = std::fflush(out.get()) == 0 && ok;
        if (!ok) fail(UM_ERR_IO, "cannot write graph.info file '", path, "': the write failed (disk full?)");
    }
    file.commit();
}

}  // namespace um::io
