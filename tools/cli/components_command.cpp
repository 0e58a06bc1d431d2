#include "components_command.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>

#include "available_memory.hpp"
#include "hdf5_trial.hpp"
#include "output_set.hpp"
#include "unimesh.h"

const std::vector<std::string> kComponentFiles = {
    "ocean.nc",      "land.nc",        "ocean.graph.info", "land.graph.info", "mesh.scrip.nc", "ocean.scrip.nc",
    "land.scrip.nc", "mesh.esmf.nc",   "ocean.esmf.nc",    "land.esmf.nc",    "rivers.json"};

namespace {

// The integer after "key": in the report (the library writes it; -1 if absent).
long report_count(const std::string &json, const char *key) {
    const std::string pattern = std::string("\"") + key + "\": ";
    const size_t at = json.find(pattern);
    return at == std::string::npos ? -1 : std::strtol(json.c_str() + at + pattern.size(), nullptr, 10);
}

// The components written into staging by the library, in this process.
int write_components(const std::string &mesh_path, const std::string &staging) {
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) {
        std::fprintf(stderr, "unimesh components: cannot create a context\n");
        return 1;
    }
    std::unique_ptr<um_context, void (*)(um_context *)> owner(ctx, um_context_destroy);
    // A file that declares more cells than the machine can hold is refused up front.
    um_context_set_memory_cap(ctx, available_memory());
    if (um_mpas_file_write_components(ctx, mesh_path.c_str(), staging.c_str()) != UM_OK) {
        std::fprintf(stderr, "unimesh components: %s\n", um_context_last_error(ctx));
        return 1;
    }
    return 0;
}

// A build's other outputs in out_dir describe the mesh.nc there: they stay
// when that is the mesh the components are made from, and go (stale) when
// the new mesh.nc replaces a different mesh.
std::vector<std::string> stale_build_files(const std::string &mesh_path, const std::string &out_dir) {
    const std::string old_mesh = out_dir + "/mesh.nc";
    std::error_code error;
    if (!std::filesystem::exists(old_mesh, error)) return {};
    if (std::filesystem::equivalent(mesh_path, old_mesh, error) || mesh_file_id(mesh_path) == mesh_file_id(old_mesh))
        return {};
    return {"graph.info", "quality.json", "quality.png", "mesh.png", "mesh.vtu", "triangles.vtu", "mesh.msh"};
}

}  // namespace

void print_river_summary(const std::string &rivers_json) {
    std::ifstream in(rivers_json);
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const long networks = report_count(json, "networks"), cells = report_count(json, "river_cells"),
               routed = report_count(json, "routed_cells") + report_count(json, "outlets"),
               outlets = report_count(json, "outlets"), inland = report_count(json, "inland_cells"),
               leaving = report_count(json, "boundary_outlets");
    long cycles = 0;
    for (size_t at = json.find("\"networks_with_cycles\""); at != std::string::npos;) {
        at = json.find("\"cycles\": ", at + 1);
        if (at != std::string::npos) cycles += std::strtol(json.c_str() + at + 10, nullptr, 10);
    }
    // (A regional mesh's rivers may leave it across its boundary instead.)
    const std::string where = leaving > 0 ? " (" + std::to_string(outlets - leaving) + " on the coast, " +
                                                std::to_string(leaving) + " on the domain's boundary)"
                                          : " on the coast";
    std::printf("rivers: %ld networks, %ld river cells: %ld drain to %ld outlets%s, %ld in networks "
                "that reach no coast; %ld cycles broken (rivers.json lists where)\n",
                networks, cells, routed, outlets, where.c_str(), inland, cycles);
}

int run_components(const std::string &mesh_path, const std::string &out_dir) {
    std::unique_ptr<OutputSet> out;
    try {
        out = std::make_unique<OutputSet>(out_dir);
    } catch (const std::runtime_error &e) {
        std::fprintf(stderr, "unimesh components: %s\n", e.what());
        return 1;
    }
    const std::string staging = out->staging_directory();
    int code = 0;
    if (is_hdf5_file(mesh_path)) {
        // libhdf5 may die on a damaged file: the whole reading and writing
        // runs in a child (hdf5_trial.hpp), as check and quality do.
        std::string death;
        code = run_in_trial_process([&] { return write_components(mesh_path, staging); }, 0, &death);
        if (code < 0) {
            std::fprintf(stderr, "unimesh components: %s: reading this netCDF-4 (HDF5) file %s%s\n",
                         mesh_path.c_str(), code == kTrialNotRun ? "was not tried: it " : "", death.c_str());
            return 1;
        }
    } else {
        code = write_components(mesh_path, staging);
    }
    if (code != 0) return 1;
    std::vector<std::string> written{"mesh.nc"};
    written.insert(written.end(), kComponentFiles.begin(), kComponentFiles.end());
    try {
        out->publish(written, stale_build_files(mesh_path, out_dir), mesh_file_id(out->staged("mesh.nc")));
    } catch (const std::runtime_error &e) {
        std::fprintf(stderr, "unimesh components: %s\n", e.what());
        return 1;
    }
    print_river_summary(out_dir + "/rivers.json");
    std::string files;
    for (const std::string &name : written) files += out_dir + "/" + name + ", ";
    std::printf("wrote %s%s/manifest.json\n", files.c_str(), out_dir.c_str());
    return 0;
}
