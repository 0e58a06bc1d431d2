// Case files for `unimesh build --case FILE.toml`: everything the flags say,
// in one file a mesh builder keeps with the mesh. TOML (toml++ from Debian):
//
//   geometry = ["coast.geojson", "rivers.geojson"]  # paths relative to the case file
//   passages = ["straits.geojson"]  # passages kept open in the ocean mesh (as --passages)
//   domain = ["box.geojson"]   # the rings of a regional mesh (as --domain)
//   kind = "coastline"         # of features without a "kind" property (as --kind)
//   spacing_km = 60            # or spacing_file = "cellWidth.nc", or spacing_preset = "EC60to30"
//   threads = 0                # 0 = all cores
//   optimise = true            # false = --no-optimise
//   out = "out"                # output directory, relative to the case file
//   [options]                  # library options by name (um_options_set_string)
//   refine_beta = 0.1
//   optim_outer_iterations = 12
//
// A flag given on the command line wins over the case file.
#pragma once

#include <string>

#include "build_command.hpp"

// Which flags the command line gave (those keep their values).
struct GivenFlags {
    bool geometry = false, passages = false, domain = false, kind = false, spacing = false, threads = false, no_optimise = false, out = false,
         vtu = false, jigsaw = false, components = false, mpas_format = false, surface = false;
};

// Reads path into args; false with a one-line *error naming the file, the
// key and the problem (syntax errors with their line).
bool read_case_file(const std::string &path, const GivenFlags &given, BuildArgs &args,
                    std::string *error);
