// unimesh: the command-line tool. Uses only the public C API.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "unimesh.h"

namespace {

int print_version() {
    std::printf("unimesh %s (library %s)\n", UM_VERSION_STRING, um_version_string());
    return 0;
}

// The default job of tools/run.sh. The mesh pipeline (refinement, optimisation,
// MPAS output) is not built yet: say so plainly instead of pretending.
int run_demo(const std::string &out_dir) {
    print_version();
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) {
        std::fprintf(stderr, "unimesh: cannot create a context\n");
        return 1;
    }
    int32_t threads = 0;
    um_context_get_threads(ctx, &threads);
    std::printf("threads available: %d\n", threads);
    std::printf("not built yet: the mesh pipeline (restricted refinement, optimisation, MPAS "
                "output); nothing written to %s\n", out_dir.c_str());
    um_context_destroy(ctx);
    return 0;
}

}  // namespace

int main(int argc, char **argv) {
    CLI::App app{"unimesh: unified Laguerre-Power meshes of the sphere for MPAS-type models"};
    app.require_subcommand(1);
    auto *version = app.add_subcommand("version", "print the version");
    auto *demo = app.add_subcommand("demo", "the default job of tools/run.sh");
    std::string out_dir = "out";
    demo->add_option("--out", out_dir, "output directory");
    CLI11_PARSE(app, argc, argv);
    if (version->parsed()) return print_version();
    if (demo->parsed()) return run_demo(out_dir);
    return 2;
}
