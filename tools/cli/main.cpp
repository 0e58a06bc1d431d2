// unimesh: the command-line tool. Uses only the public C API.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "unimesh.h"

namespace {

int print_version() {
    std::printf("unimesh %s (library %s)\n", UM_VERSION_STRING, um_version_string());
    return 0;
}

// A global quasi-uniform point set: the vertices of an icosahedron whose
// faces are split `level` times (10 * 4^level + 2 points), as lon/lat.
void icosahedral_lonlat(int level, std::vector<double> &lon, std::vector<double> &lat) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<std::array<double, 3>> pts = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                                              {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                                              {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    std::vector<std::array<int, 3>> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    auto unit = [](std::array<double, 3> v) {
        double r = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        return std::array<double, 3>{v[0] / r, v[1] / r, v[2] / r};
    };
    for (auto &v : pts) v = unit(v);
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            pts.push_back(unit({pts[a][0] + pts[b][0], pts[a][1] + pts[b][1], pts[a][2] + pts[b][2]}));
            return mid[key] = static_cast<int>(pts.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (auto &f : faces) {
            int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
            next.insert(next.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
        }
        faces.swap(next);
    }
    for (auto &v : pts) {
        lon.push_back(std::atan2(v[1], v[0]) * 180.0 / M_PI);
        lat.push_back(std::asin(std::max(-1.0, std::min(1.0, v[2]))) * 180.0 / M_PI);
    }
}

// The default job of tools/run.sh, until the mesh pipeline exists: triangulate
// a global icosahedral point set through the C API, check it, and say plainly
// what is not built yet.
int run_demo(const std::string &out_dir, int level) {
    print_version();
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) {
        std::fprintf(stderr, "unimesh: cannot create a context\n");
        return 1;
    }
    int32_t threads = 0;
    um_context_get_threads(ctx, &threads);
    std::vector<double> lon, lat;
    icosahedral_lonlat(level, lon, lat);
    auto t0 = std::chrono::steady_clock::now();
    um_triangulation *tri = nullptr;
    um_status s = um_triangulation_create(ctx, static_cast<int64_t>(lon.size()), lon.data(),
                                          lat.data(), nullptr, &tri);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s != UM_OK) {
        std::fprintf(stderr, "unimesh: %s\n", um_context_last_error(ctx));
        um_context_destroy(ctx);
        return 1;
    }
    int64_t nv = 0, nt = 0, nh = 0;
    um_triangulation_counts(tri, &nv, &nt, &nh);
    um_status check = um_triangulation_check(tri);
    std::printf("triangulated a level-%d icosahedral grid on %d threads: %lld vertices, %lld "
                "triangles, %lld hidden, in %.3f s; exact check: %s\n",
                level, threads, static_cast<long long>(nv), static_cast<long long>(nt),
                static_cast<long long>(nh), seconds,
                check == UM_OK ? "passed" : um_context_last_error(ctx));
    std::printf("not built yet: restricted refinement, optimisation and MPAS output; nothing "
                "written to %s\n", out_dir.c_str());
    um_triangulation_destroy(tri);
    um_context_destroy(ctx);
    return check == UM_OK ? 0 : 1;
}

}  // namespace

int main(int argc, char **argv) {
    CLI::App app{"unimesh: unified Laguerre-Power meshes of the sphere for MPAS-type models"};
    app.require_subcommand(1);
    auto *version = app.add_subcommand("version", "print the version");
    auto *demo = app.add_subcommand("demo", "the default job of tools/run.sh");
    std::string out_dir = "out";
    int level = 7;
    demo->add_option("--out", out_dir, "output directory");
    demo->add_option("--level", level, "icosahedral subdivision level of the demo grid")
        ->check(CLI::Range(0, 10));
    CLI11_PARSE(app, argc, argv);
    if (version->parsed()) return print_version();
    if (demo->parsed()) return run_demo(out_dir, level);
    return 2;
}
