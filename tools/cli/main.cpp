// unimesh: the command-line tool. Uses only the public C API.
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "build_command.hpp"
#include "case_file.hpp"
#include "components_command.hpp"
#include "hdf5_trial.hpp"
#include "mesh_file_commands.hpp"
#include "unimesh.h"

namespace {

int print_version() {
    std::printf("unimesh %s (library %s)\n", UM_VERSION_STRING, um_version_string());
    return 0;
}

// check and quality read a netCDF-4 (HDF5) file wholly in a trial process
// (hdf5_trial.hpp): a damaged one may kill libhdf5. No time limit: a big
// mesh takes long to check.
int judge_mesh_file(const char *command, const std::string &path, const std::function<int()> &judge) {
    if (!is_hdf5_file(path)) return judge();
    std::string death;
    const int code = run_in_trial_process(judge, 0, &death);
    if (code >= 0) return code;
    if (code == kTrialNotRun)
        std::fprintf(stderr, "unimesh %s: %s: reading this netCDF-4 (HDF5) file: it %s\n", command, path.c_str(),
                     death.c_str());
    else
        std::fprintf(stderr, "unimesh %s: %s: reading this netCDF-4 (HDF5) file %s: the file is damaged\n", command,
                     path.c_str(), death.c_str());
    return 1;
}

}  // namespace

int main(int argc, char **argv) {
    CLI::App app{"unimesh: unified Laguerre-Power meshes of the sphere for MPAS-type models"};
    app.require_subcommand(1);
    // `unimesh --version` as well as `unimesh version` (the same line).
    app.set_version_flag("--version", std::string("unimesh ") + UM_VERSION_STRING + " (library " + um_version_string() + ")");
    auto *version = app.add_subcommand("version", "print the version");
    auto *build = app.add_subcommand("build", "refine a mesh to features and a spacing, write it");
    BuildArgs b;
    std::string case_file;
    build->add_option("--case", case_file, "case file (TOML): geometry, spacing, options, ...; flags win")
        ->check(CLI::ExistingFile);
    build->add_option("--geometry", b.geometry, "GeoJSON features (coastlines, lakes, rivers); repeatable")
        ->check(CLI::ExistingFile);
    build->add_option("--passages", b.passages,
                      "GeoJSON lines or points across which the ocean mesh is kept open (critical "
                      "passages; a feature's kind must be \"passage\" or absent); repeatable")
        ->check(CLI::ExistingFile);
    build->add_option("--domain", b.domain,
                      "GeoJSON polygons bounding a regional mesh: only the cells inside them are written "
                      "(a feature's kind must be \"domain\" or absent); repeatable")
        ->check(CLI::ExistingFile);
    build->add_option("--kind,--default-kind", b.default_kind,
                      "kind of a GeoJSON feature without a \"kind\" property: coastline, lake, river, "
                      "watershed, other or passage (default: such a feature is an error)");
    // (NaN stands for "not given" in BuildArgs: one given is named here.)
    auto *km = build->add_option("--spacing-km", b.spacing_km, "constant spacing h, km")->check([](const std::string &s) {
        char *end = nullptr;
        return std::isnan(std::strtod(s.c_str(), &end)) ? s + " is not a number" : std::string();
    });
    auto *file = build->add_option("--spacing-file", b.spacing_file,
                                   "MPAS-tools spacing file: netCDF lon, lat, cellWidth(lat, lon) km");
    auto *preset = build->add_option("--spacing-preset", b.spacing_preset,
                                     "E3SM spacing: QU<km>, EC60to30, RRS18to6, ...");
    build->add_option("--spacing-gradient", b.spacing_gradient,
                      "mesh a grid spacing steeper than G km per km gradient-limited to G, so that "
                      "a feature finer than its surroundings gets a transition (default 0.25; 0: as given)");
    build->add_option("--surface", b.surface,
                      "sphere (the default: radius 6371.22 km, or --option sphere_radius=M), wgs84, or "
                      "ellipsoid:A,F (semi-major axis A in m, flattening F in [0, 0.02]; over --option's "
                      "sphere_radius and surface_flattening); spacing in km is geodesic km on the surface")
        ->check([](const std::string &s) { return s.empty() ? std::string("an empty surface") : std::string(); });
    km->excludes(file)->excludes(preset);
    file->excludes(preset);
    build->add_option("--threads", b.threads, "threads (0 = all cores)")->check(CLI::Range(0, 1024));
    build->add_flag("--no-optimise", b.no_optimise, "skip the primal-dual optimisation");
    build->add_flag("--vtu", b.vtu, "also write mesh.vtu and triangles.vtu (ParaView)");
    build->add_flag("--jigsaw", b.jigsaw, "also write mesh.msh (JIGSAW)");
    build->add_option("--mpas-format", b.mpas_format,
                      "container of mesh.nc: auto (netCDF 64-bit offset, CDF-5 for large meshes; the default) "
                      "or netcdf4 (HDF5)")
        ->check(CLI::IsMember({"auto", "netcdf4"}));
    build->add_flag("--components", b.components,
                    "also write the component meshes and coupler grids: ocean.nc, land.nc, "
                    "ocean.graph.info, land.graph.info, {mesh,ocean,land}.scrip.nc, "
                    "{mesh,ocean,land}.esmf.nc, rivers.json");
    build->add_flag("--verbose", b.verbose, "print the library's progress messages (per optimisation iteration)");
    build->add_option("--option", b.options, "library options, \"name=value;...\" (e.g. refine_beta=0.1)");
    build->add_option("--memory-cap", b.memory_cap,
                      "memory cap: auto (the available memory, the default), 0 (none), or bytes with K, M, G, T");
    build->add_option("--out", b.out_dir, "output directory (mesh.nc, graph.info, quality.json, quality.png, mesh.png, manifest.json)");
    auto *check = app.add_subcommand("check", "check an MPAS mesh file against the mesh contract");
    std::string check_path;
    check->add_option("MESH.nc", check_path, "MPAS mesh file")->required()->check(CLI::ExistingFile);
    auto *quality = app.add_subcommand("quality", "the Figure 10 quality metrics of an MPAS mesh file");
    std::string quality_path;
    bool quality_json = false;
    quality->add_option("MESH.nc", quality_path, "MPAS mesh file")->required()->check(CLI::ExistingFile);
    quality->add_flag("--json", quality_json, "one JSON object instead of the table");
    auto *components = app.add_subcommand(
        "components", "the component meshes and coupler grids of a unified MPAS mesh file: mesh.nc (with the maps), "
                      "ocean.nc, land.nc, their graph.info files, SCRIP and ESMF grids, rivers.json");
    std::string components_path, components_out;
    components->add_option("MESH.nc", components_path, "MPAS mesh file with cellOceanMask and cellLandMask")
        ->required()
        ->check(CLI::ExistingFile);
    components->add_option("--out", components_out, "output directory")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError &e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line, naming the flag and the value, as every other error.
        std::fprintf(stderr, "unimesh: %s (see unimesh %s--help)\n", e.what(),
                     build->parsed() ? "build " : "");
        return 2;
    }
    if (check->parsed()) return judge_mesh_file("check", check_path, [&] { return run_check(check_path); });
    if (quality->parsed())
        return judge_mesh_file("quality", quality_path, [&] { return run_quality(quality_path, quality_json); });
    if (components->parsed()) return run_components(components_path, components_out);
    if (version->parsed()) return print_version();
    if (build->parsed()) {
        b.spacing_gradient_given = build->count("--spacing-gradient") > 0;
        if (!case_file.empty()) {
            GivenFlags given;
            given.geometry = build->count("--geometry") > 0;
            given.passages = build->count("--passages") > 0;
            given.domain = build->count("--domain") > 0;
            given.kind = build->count("--kind") > 0;
            given.spacing = build->count("--spacing-km") + build->count("--spacing-file") +
                                build->count("--spacing-preset") > 0;
            given.threads = build->count("--threads") > 0;
            given.no_optimise = build->count("--no-optimise") > 0;
            given.vtu = build->count("--vtu") > 0;
            given.jigsaw = build->count("--jigsaw") > 0;
            given.components = build->count("--components") > 0;
            given.mpas_format = build->count("--mpas-format") > 0;
            given.out = build->count("--out") > 0;
            given.surface = build->count("--surface") > 0;
            std::string error;
            if (!read_case_file(case_file, given, b, &error)) {
                std::fprintf(stderr, "unimesh build: %s\n", error.c_str());
                return 1;
            }
        }
        return run_build(b);
    }
    return 2;
}
