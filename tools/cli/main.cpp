// unimesh: the command-line tool. Uses only the public C API.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "build_command.hpp"
#include "unimesh.h"

namespace {

int print_version() {
    std::printf("unimesh %s (library %s)\n", UM_VERSION_STRING, um_version_string());
    return 0;
}

}  // namespace

int main(int argc, char **argv) {
    CLI::App app{"unimesh: unified Laguerre-Power meshes of the sphere for MPAS-type models"};
    app.require_subcommand(1);
    auto *version = app.add_subcommand("version", "print the version");
    auto *build = app.add_subcommand("build", "refine a mesh to features and a spacing, write it");
    BuildArgs b;
    build->add_option("--geometry", b.geometry, "GeoJSON features (coastlines, lakes, rivers); repeatable")
        ->check(CLI::ExistingFile);
    auto *km = build->add_option("--spacing-km", b.spacing_km, "constant spacing h, km");
    auto *file = build->add_option("--spacing-file", b.spacing_file,
                                   "MPAS-tools spacing file: netCDF lon, lat, cellWidth(lat, lon) km");
    auto *preset = build->add_option("--spacing-preset", b.spacing_preset,
                                     "E3SM spacing: QU<km>, EC60to30, RRS18to6, ...");
    km->excludes(file)->excludes(preset);
    file->excludes(preset);
    build->add_option("--threads", b.threads, "threads (0 = all cores)")->check(CLI::Range(0, 1024));
    build->add_flag("--no-optimise", b.no_optimise, "skip the primal-dual optimisation");
    build->add_flag("--verbose", b.verbose, "print the library's progress messages (per optimisation iteration)");
    build->add_option("--option", b.options, "library options, \"name=value;...\" (e.g. refine_beta=0.1)");
    build->add_option("--out", b.out_dir, "output directory (mesh.nc, graph.info, mesh.vtu, quality.json)");
    CLI11_PARSE(app, argc, argv);
    if (version->parsed()) return print_version();
    if (build->parsed()) return run_build(b);
    return 2;
}
