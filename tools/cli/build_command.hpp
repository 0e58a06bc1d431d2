// `unimesh build`: geometry + spacing -> refined mesh -> files in the output
// directory. Uses the public C API only.
#pragma once

#include <cmath>
#include <string>
#include <vector>

struct BuildArgs {
    std::vector<std::string> geometry;  // GeoJSON files
    std::vector<std::string> passages;  // GeoJSON files of passages (UM_FEATURE_PASSAGE)
    // GeoJSON files of the rings of a regional mesh's domain (UM_FEATURE_DOMAIN).
    std::vector<std::string> domain;
    // The kind of a GeoJSON feature without a "kind" property (coastline,
    // lake, river, watershed or other); "" = such a feature is an error.
    std::string default_kind;
    double spacing_km = std::nan("");   // one of these three (NaN: not given)
    std::string spacing_file, spacing_preset;
    // The library's spacing_gradient option (km per km; 0: the spacing as
    // given), when given (else the option's value stands).
    double spacing_gradient = 0;
    bool spacing_gradient_given = false;
    // The surface: "sphere" (sphere_radius, by default E3SM's 6371.22 km),
    // "wgs84", or "ellipsoid:A,F" (semi-major axis in m, flattening); ""
    // (not given): the options' sphere_radius and surface_flattening stand.
    // surface_source names where it came from in messages.
    std::string surface, surface_source = "--surface";
    int threads = 0;
    bool no_optimise = false;
    // The outputs beyond the default set (mesh.nc, graph.info, quality.json,
    // the pictures): ParaView's mesh.vtu and triangles.vtu, JIGSAW's
    // mesh.msh. Large meshes spend minutes writing them.
    bool vtu = false, jigsaw = false;
    // The component meshes and coupler grids (um_mesh_write_components):
    // ocean.nc, land.nc, their graph.info files, SCRIP and ESMF grids of the
    // base and both components, rivers.json; mesh.nc then has the maps.
    bool components = false;
    // mesh.nc's container: "auto" (64-bit offset, CDF-5 when a variable
    // needs it) or "netcdf4".
    std::string mpas_format = "auto";
    std::string options;  // "name=value;..." for um_options_set_string
    // A case file's [options], set before the case file's surface, then
    // --option, then --surface: flags win.
    std::string case_options;
    std::string out_dir = "out";
    bool progress_bar = false;
    bool verbose = false;  // the library's info messages on stderr
    // The context's memory cap: "auto" (the machine's available memory, so
    // an impossible size is refused up front), "0" (none), or bytes with an
    // optional K, M, G or T (powers of 1024).
    std::string memory_cap = "auto";
};

// 0 when every file was written; prints one-line errors to stderr.
int run_build(const BuildArgs &args);
