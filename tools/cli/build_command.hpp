// `unimesh build`: geometry + spacing -> refined mesh -> files in the output
// directory. Uses the public C API only.
#pragma once

#include <cmath>
#include <string>
#include <vector>

struct BuildArgs {
    std::vector<std::string> geometry;  // GeoJSON files
    double spacing_km = std::nan("");   // one of these three (NaN: not given)
    std::string spacing_file, spacing_preset;
    int threads = 0;
    bool no_optimise = false;
    std::string options;  // "name=value;..." for um_options_set_string
    std::string out_dir = "out";
    bool progress_bar = false;
    bool verbose = false;  // the library's info messages on stderr
};

// 0 when every file was written; prints one-line errors to stderr.
int run_build(const BuildArgs &args);
