#include "components/components.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "components/cut_mesh.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "io/coupler_grids.hpp"
#include "io/graph_info.hpp"
#include "io/mpas_writer.hpp"
#include "io/replacing_file.hpp"
#include "unimesh.h"

namespace um::components {

using dual::kNone;
using dual::MpasMesh;

namespace {

// to[base element] = its index in the component, kNone elsewhere.
std::vector<int32_t> forward_map(const std::vector<int32_t> &base_of, int32_t base_count) {
    std::vector<int32_t> to(static_cast<size_t>(base_count), kNone);
    for (size_t i = 0; i < base_of.size(); ++i) to[base_of[i]] = static_cast<int32_t>(i);
    return to;
}

MpasMesh component(Context &ctx, const MpasMesh &base, const std::vector<int32_t> &mask, const char *name) {
    std::vector<uint8_t> keep(mask.begin(), mask.end());
    int64_t cells = 0;
    for (uint8_t k : keep) cells += k != 0;
    if (cells == 0)
        fail(UM_ERR_INVALID_ARGUMENT, "the ", name, " component has no cells: the mesh needs closed coastlines "
             "with both ocean and land to be split");
    return cut_mesh(ctx, base, keep);
}

void write_text(const std::string &path, const std::string &text) {
    io::ReplacingFile file(path, "river report");
    {
        std::ofstream out(file.temporary_path(), std::ios::binary);
        out << text;
        out.flush();
        if (!out) fail(UM_ERR_IO, "cannot write river report '", path, "'");
    }
    file.commit();
}

// The notes as a JSON list; numbers locale-independent (core/text.hpp).
std::string notes_json(const std::vector<dual::RiverNetworkNote> &notes, const CellLatLon &cell_lat_lon) {
    std::string json = "[";
    for (size_t i = 0; i < notes.size(); ++i) {
        const dual::RiverNetworkNote &n = notes[i];
        double lat, lon;
        cell_lat_lon(n.cell, lat, lon);
        json += concat(i ? ", " : "", "{\"network\": ", n.network + 1, ", \"cells\": ", n.cells,
                       ", \"cycles\": ", n.cycles, ", \"cell\": ", n.cell + 1,
                       ", \"lat\": ", lat * 180 / M_PI, ", \"lon\": ", lon * 180 / M_PI, "}");
    }
    return json + "]";
}

}  // namespace

ComponentMeshes split_components(Context &ctx, MpasMesh &base) {
    if (base.cell_ocean_mask.empty() || base.cell_land_mask.empty())
        fail(UM_ERR_INVALID_ARGUMENT, "the mesh has no ocean and land cell masks (cellOceanMask, cellLandMask): "
             "it was made without closed coastlines");
    ComponentMeshes parts{component(ctx, base, base.cell_ocean_mask, "ocean"),
                          component(ctx, base, base.cell_land_mask, "land")};
    base.ocean_cell = forward_map(parts.ocean.base_cell, base.n_cells);
    base.ocean_edge = forward_map(parts.ocean.base_edge, base.n_edges);
    base.ocean_vertex = forward_map(parts.ocean.base_vertex, base.n_vertices);
    base.land_cell = forward_map(parts.land.base_cell, base.n_cells);
    base.land_edge = forward_map(parts.land.base_edge, base.n_edges);
    base.land_vertex = forward_map(parts.land.base_vertex, base.n_vertices);
    return parts;
}

std::string river_report_json(const dual::RiverReport &report, const MpasMesh &base) {
    return river_report_json(report, [&](int32_t cell, double &lat, double &lon) {
        lat = base.lat_cell[cell], lon = base.lon_cell[cell];
    });
}

std::string river_report_json(const dual::RiverReport &report, const CellLatLon &cell_lat_lon) {
    int64_t inland_cells = 0;
    for (const auto &n : report.inland) inland_cells += n.cells;
    return concat("{\"networks\": ", report.networks, ", \"river_cells\": ", report.river_cells,
                  ", \"routed_cells\": ", report.routed_cells, ", \"outlets\": ", report.outlets,
                  ", \"boundary_outlets\": ", report.boundary_outlets,
                  ", \"bridges\": ", report.bridges, ", \"inland_cells\": ", inland_cells,
                  ", \"inland_networks\": ", notes_json(report.inland, cell_lat_lon),
                  ", \"networks_with_cycles\": ", notes_json(report.with_cycles, cell_lat_lon), "}\n");
}

void require_directory(const std::string &directory) {
    struct stat st {};
    if (directory.empty() || ::stat(directory.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        fail(UM_ERR_IO, "directory = '", directory, "' is not an existing directory");
}

namespace {

// The files of one call, written into a fresh directory inside the output
// directory and renamed into it together at the end: a failure part-way
// leaves the previous set as it was, not a mix of two sets.
class StagedSet {
public:
    explicit StagedSet(const std::string &directory) : dir_(directory + (directory.back() == '/' ? "" : "/")) {
        static std::atomic<uint64_t> serial{0};
        stage_ = concat(dir_, ".unimesh-components-", static_cast<int64_t>(::getpid()), "-", serial++);
        if (::mkdir(stage_.c_str(), 0777) != 0)
            fail(UM_ERR_IO, "cannot write into directory '", directory, "': ", std::strerror(errno));
    }
    ~StagedSet() {
        for (const std::string &name : names_) ::unlink(staged(name).c_str());
        ::rmdir(stage_.c_str());
    }
    StagedSet(const StagedSet &) = delete;
    StagedSet &operator=(const StagedSet &) = delete;

    std::string add(const std::string &name) {
        names_.push_back(name);
        return staged(name);
    }
    void publish() {
        for (const std::string &name : names_)
            if (std::rename(staged(name).c_str(), (dir_ + name).c_str()) != 0)
                fail(UM_ERR_IO, "cannot move '", name, "' into '", dir_, "': ", std::strerror(errno));
    }

private:
    std::string staged(const std::string &name) const { return stage_ + "/" + name; }
    std::string dir_, stage_;
    std::vector<std::string> names_;
};

}  // namespace

dual::RiverReport write_component_files(Context &ctx, MpasMesh &base, const std::string &directory) {
    require_directory(directory);
    const dual::RiverReport report = dual::route_rivers(base);
    ComponentMeshes parts = split_components(ctx, base);
    // The last point to cancel: from here the set is written through.
    ctx.progress("component files", 0.0);
    StagedSet set(directory);
    io::write_mpas_mesh(base, set.add("mesh.nc"));
    io::write_mpas_mesh(parts.ocean, set.add("ocean.nc"));
    io::write_mpas_mesh(parts.land, set.add("land.nc"));
    io::write_graph_info(parts.ocean, set.add("ocean.graph.info"));
    io::write_graph_info(parts.land, set.add("land.graph.info"));
    const struct {
        const MpasMesh &mesh;
        const char *name;
    } grids[] = {{base, "mesh"}, {parts.ocean, "ocean"}, {parts.land, "land"}};
    for (const auto &g : grids) {
        io::write_scrip_grid(g.mesh, set.add(std::string(g.name) + ".scrip.nc"));
        io::write_esmf_mesh(g.mesh, set.add(std::string(g.name) + ".esmf.nc"));
    }
    write_text(set.add("rivers.json"), river_report_json(report, base));
    set.publish();
    return report;
}

}  // namespace um::components
