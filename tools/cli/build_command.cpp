#include "build_command.hpp"

#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <memory>
#include <optional>
#include <netcdf.h>
#include <stdexcept>
#include <vector>

#include "available_memory.hpp"
#include "components_command.hpp"
#include "mpas_extras.hpp"
#include "nc_read.hpp"
#include "output_set.hpp"
#include "hdf5_trial.hpp"
#include "unimesh.h"

namespace {

// Stops with a one-line message naming what failed and the library's reason.
struct Failure {
    std::string message;
};

void check(um_status s, um_context *ctx, const std::string &what) {
    if (s != UM_OK) throw Failure{what + ": " + um_context_last_error(ctx)};
}

// On a terminal: one line redrawn, "stage [#####.....]  45%"; otherwise a
// plain line per stage (logs, CI).
int32_t report_progress(void *user, const char *stage, double fraction) {
    auto *last = static_cast<std::string *>(user);
    if (isatty(fileno(stderr))) {
        constexpr int kWidth = 30;
        const double f = fraction < 0 ? 0 : (fraction > 1 ? 1 : fraction);
        const int filled = static_cast<int>(f * kWidth + 0.5);
        std::fprintf(stderr, "\r%-18s [%.*s%.*s] %3d%%", stage, filled, "##############################",
                     kWidth - filled, "..............................", static_cast<int>(100 * f + 0.5));
        std::fflush(stderr);
    } else if (*last != stage) {
        std::fprintf(stderr, "%s\n", stage);
    }
    *last = stage;
    return 0;
}

// --memory-cap as bytes (see BuildArgs::memory_cap).
int64_t memory_cap_bytes(const std::string &text) {
    if (text == "auto") return available_memory();
    double value = 0;
    const char *begin = text.data(), *end = text.data() + text.size();
    const auto [rest, error] = std::from_chars(begin, end, value);
    int shift = 0;
    const std::string suffix(rest, end);
    if (suffix == "K" || suffix == "k") shift = 10;
    else if (suffix == "M") shift = 20;
    else if (suffix == "G") shift = 30;
    else if (suffix == "T") shift = 40;
    else if (!suffix.empty()) shift = -1;
    const double bytes = std::ldexp(value, shift);
    if (error != std::errc() || rest == begin || shift < 0 || !(value >= 0) || !(bytes < 9e18))
        throw Failure{"--memory-cap " + text + ": not auto, 0 or a size in bytes (with K, M, G or T)"};
    return static_cast<int64_t>(bytes);
}

// The surface into the options (over --option's): wgs84 or ellipsoid:A,F
// set sphere_radius (the semi-major axis) and surface_flattening; sphere
// sets the flattening to 0 and leaves the radius (the default, or
// --option's); not given, both stand as the options have them.
void set_surface(um_context *ctx, um_options *opts, const std::string &surface, const std::string &source) {
    constexpr double kWgs84A = 6378137.0, kWgs84F = 1 / 298.257223563;
    const std::string where = source + " " + surface;
    if (surface.empty()) return;
    if (surface == "sphere") {
        check(um_options_set_double(opts, UM_OPT_SURFACE_FLATTENING, 0.0), ctx, where);
        return;
    }
    double a = kWgs84A, f = kWgs84F;
    const std::string prefix = "ellipsoid:";
    if (surface.compare(0, prefix.size(), prefix) == 0) {
        const char *begin = surface.data() + prefix.size(), *end = surface.data() + surface.size();
        const auto [comma, error_a] = std::from_chars(begin, end, a);
        const bool split = comma != end && *comma == ',';
        const auto [rest, error_f] = split ? std::from_chars(comma + 1, end, f) : std::from_chars_result{end, std::errc()};
        if (error_a == std::errc::result_out_of_range || error_f == std::errc::result_out_of_range)
            throw Failure{where + ": a number out of the range of doubles"};
        if (error_a != std::errc() || !split || error_f != std::errc() || rest != end)
            throw Failure{where + ": not ellipsoid:A,F (semi-major axis in m, flattening)"};
    } else if (surface != "wgs84") {
        throw Failure{where + ": not sphere, wgs84 or ellipsoid:A,F"};
    }
    check(um_options_set_double(opts, UM_OPT_SPHERE_RADIUS, a), ctx, where);
    check(um_options_set_double(opts, UM_OPT_SURFACE_FLATTENING, f), ctx, where);
}

// --kind as a UM_FEATURE_* value (0: none given).
int32_t kind_code(const std::string &name) {
    static const struct {
        const char *name;
        int32_t code;
    } kinds[] = {{"coastline", UM_FEATURE_COASTLINE}, {"lake", UM_FEATURE_LAKE}, {"river", UM_FEATURE_RIVER},
                 {"watershed", UM_FEATURE_WATERSHED}, {"other", UM_FEATURE_OTHER},
                 {"passage", UM_FEATURE_PASSAGE}};
    if (name.empty()) return 0;
    for (const auto &k : kinds)
        if (name == k.name) return k.code;
    throw Failure{"--kind " + name + ": not coastline, lake, river, watershed, other or passage"};
}

// The features of a --passages or --domain file (flag): all of one kind,
// whatever else the file holds is refused (a coastline there would silently
// become part of the mesh).
void add_parts_of_kind(um_context *ctx, um_features *f, const std::string &flag, const std::string &path,
                       int32_t kind_code, const char *kind_name) {
    int64_t before = 0, after = 0;
    um_features_counts(f, &before, nullptr, nullptr);
    check(um_features_read_geojson(f, path.c_str(), nullptr, kind_code), ctx, flag + " " + path);
    um_features_counts(f, &after, nullptr, nullptr);
    if (after == before) throw Failure{flag + " " + path + ": holds no " + kind_name + " feature"};
    std::vector<int32_t> kind(static_cast<size_t>(after)), id(static_cast<size_t>(after));
    check(um_features_copy_parts(f, nullptr, nullptr, kind.data(), id.data(), after), ctx, flag + " " + path);
    for (int64_t p = before; p < after; ++p)
        if (kind[p] != kind_code)
            throw Failure{flag + " " + path + ": the feature of id " + std::to_string(id[p]) + " has a kind other than \"" +
                          kind_name + "\"; give it with --geometry"};
}

bool holds_domain(um_context *ctx, um_features *f) {
    int64_t parts = 0;
    um_features_counts(f, &parts, nullptr, nullptr);
    if (parts == 0) return false;  // (the copy below would be of nothing: an error)
    std::vector<int32_t> kind(static_cast<size_t>(parts));
    check(um_features_copy_parts(f, nullptr, nullptr, kind.data(), nullptr, parts), ctx, "features");
    return std::find(kind.begin(), kind.end(), UM_FEATURE_DOMAIN) != kind.end();
}

um_spacing *make_spacing(um_context *ctx, const BuildArgs &a) {
    um_spacing *h = nullptr;
    const bool km = !std::isnan(a.spacing_km);
    int given = km + !a.spacing_file.empty() + !a.spacing_preset.empty();
    if (given != 1)
        throw Failure{"give exactly one of --spacing-km, --spacing-file, --spacing-preset"};
    if (km)  // the library names a value that is not > 0
        check(um_spacing_create_constant(ctx, a.spacing_km, &h), ctx, "--spacing-km");
    else if (!a.spacing_file.empty())
        check(um_spacing_create_from_file(ctx, a.spacing_file.c_str(), &h), ctx,
              "--spacing-file " + a.spacing_file);
    else
        check(um_spacing_create_preset(ctx, a.spacing_preset.c_str(), &h), ctx,
              "--spacing-preset " + a.spacing_preset);
    return h;
}

void print_log(void *, int32_t, const char *message) {
    if (isatty(fileno(stderr))) std::fprintf(stderr, "\r%-60s\r", "");
    std::fprintf(stderr, "%s\n", message);
}

std::string quality_json(um_context *ctx, um_mesh *m) {
    int64_t needed = 0;
    um_mesh_quality_json(m, nullptr, 0, &needed);
    std::string text(static_cast<size_t>(needed), '\0');
    check(um_mesh_quality_json(m, text.data(), needed, nullptr), ctx, "quality report");
    text.resize(static_cast<size_t>(needed) - 1);
    return text;
}

// The number after the last of `anchors`, each found after the one before,
// in `report` (one mesh's JSON report: the text of one object); NaN when
// absent or null (not finite).
double number_after(const std::string &report, std::initializer_list<std::string> anchors) {
    size_t at = 0, length = 0;
    for (const std::string &a : anchors)
        if (at != std::string::npos) at = report.find(a, at + length), length = a.size();
    double value = NAN;
    if (at != std::string::npos)  // locale-independent, as the library writes it
        std::from_chars(report.data() + at + length, report.data() + report.size(), value);
    return value;
}

// `key` of `member` in the report.
double member_number(const std::string &report, const char *member, const char *key) {
    return number_after(report, {std::string("\"") + member + "\"", std::string("\"") + key + "\": "});
}

// The mesh's own report in um_mesh_quality_json's text (before the refined
// mesh's, "before_optimisation"), and the refined mesh's (empty when the
// mesh was not optimised): the object after that key, to its closing brace
// (no string in a report holds a brace).
std::string own_report(const std::string &json) { return json.substr(0, json.find("\"before_optimisation\"")); }
std::string refined_report(const std::string &json) {
    const size_t key = json.find("\"before_optimisation\"");
    const size_t open = key == std::string::npos ? key : json.find('{', key);
    if (open == std::string::npos) return {};
    int depth = 0;
    for (size_t i = open; i < json.size(); ++i) {
        depth += json[i] == '{' ? 1 : json[i] == '}' ? -1 : 0;
        if (depth == 0) return json.substr(open, i + 1 - open);
    }
    return {};
}

// The quality lines of one mesh's report (own_report or refined_report).
void print_quality(const char *what, const std::string &report) {
    auto d = [&](const char *member, const char *key) { return member_number(report, member, key); };
    auto n = [&](const char *anchor) { return number_after(report, {anchor}); };
    const double triangles = n("\"triangles\": ");
    std::printf("%-9s quality: area-length ratio min %.3f mean %.3f; primal-dual min %.3f mean %.4f; "
                "max angle %.1f deg; %.0f obtuse triangles (%.3f %%), %.0f not containing their "
                "orthocentre\n",
                what, d("area_length_ratio", "min"), d("area_length_ratio", "mean"), d("primal_dual", "min"),
                d("primal_dual", "mean"), d("angle_max_deg", "max"), n("\"obtuse_triangles\": "),
                100.0 * n("\"obtuse_triangles\": ") / (triangles > 0 ? triangles : 1.0), n("\"not_well_centred\": "));
    // What certifies the mesh for the MPAS operators (unimesh.h, um_mesh_quality_json).
    std::printf("%-9s operator diagnostics: centroid offset rms %.3g max %.3g; dual-edge offset rms %.3g "
                "max %.3g; primal-edge offset rms %.3g max %.3g; dcEdge/h min %.3f max %.3f mean %.3f "
                "std %.3g\n",
                what, d("centroid_offset", "rms"), d("centroid_offset", "max"), d("dual_edge_offset", "rms"),
                d("dual_edge_offset", "max"), d("primal_edge_offset", "rms"), d("primal_edge_offset", "max"),
                d("cell_spacing_ratio", "min"), d("cell_spacing_ratio", "max"),
                d("cell_spacing_ratio", "mean"), d("cell_spacing_ratio", "std"));
    // The time-step floor: an explicit ocean model's step is set by its shortest dcEdge.
    std::printf("%-9s ocean floor %.2f h: dcEdge/h min %.3f over %.0f ocean edges (%.3f over all edges), "
                "%.0f ocean edges below the floor\n",
                what, d("ocean_floor", "floor"), d("ocean_floor", "min_ratio"), d("ocean_floor", "ocean_edges"),
                d("ocean_floor", "all_edges_min_ratio"), d("ocean_floor", "below_floor"));
    // Passages: the ones the mesh closed (quality.json lists where), the ones kept open.
    std::printf("%-9s ocean connectivity: %.0f regions in %.0f water bodies, %.0f passages closed; "
                "%.0f cells kept open by passages, %.0f of their edges below the floor\n",
                what, n("\"regions\": {\"count\": "), n("\"water_bodies\": "),
                n("\"closed_passages\": {\"count\": "), n("\"kept_open\": {\"cells\": "),
                d("kept_open", "below_floor"));
    // What the floor's filtering costs the coastline.
    if (!std::isnan(d("coastline_fidelity", "restricted_edges")))
        std::printf("%-9s coastline fidelity: %.0f restricted edges on closed coastlines, eps/(beta h) mean %.3f "
                    "max %.3f, %.0f beyond beta h\n",
                    what, d("coastline_fidelity", "restricted_edges"), d("coastline_fidelity", "mean"),
                    d("coastline_fidelity", "max"), d("coastline_fidelity", "beyond_beta"));
    std::fflush(stdout);
}

// mesh.png draws every cell, about 16 us of CPU a cell (10 s for 655 k):
// above this many (half a minute; 17 minutes at 3 km's 66 M cells, for a
// picture too dense to read) it is left out, with a note.
constexpr int64_t kMapCellLimit = 2000000;

int64_t cell_count(const um_mesh *m) {
    int64_t cells = 0, triangles = 0, restricted = 0, coarser = 0;
    um_mesh_counts(m, &cells, &triangles, &restricted, &coarser);
    return cells;
}

// quality.png (the Figure 10 histograms, tools/plot_quality.py) and
// mesh.png (a map of the cells and the input lines, tools/plot_mesh.py),
// drawn with Debian's matplotlib. A missing Python or matplotlib costs the
// picture, not the mesh: a warning, and the exit status stays that of the
// mesh files. Debian's own Python (where setup.sh installs the packages)
// first. The scripts installed beside this executable, else the source tree's.
std::string plot_script(const std::string &name) {
    char exe[4096];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        std::string dir(exe, static_cast<size_t>(n));
        dir.erase(dir.find_last_of('/') + 1);
        const std::string installed = dir + UNIMESH_INSTALLED_PLOT_DIR + "/" + name;
        if (access(installed.c_str(), R_OK) == 0) return installed;
    }
    return std::string(UNIMESH_PLOT_DIR) + "/" + name;
}

// Runs `script` with `arguments`; false (after a warning naming `shown`) if
// it fails.
const char *plot_python() { return access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3"; }

// A plot script running beside the build (pid < 0: it could not start),
// and the socket it waits on for its start (tools/plot_signal.py) until
// tell_plot says its input is written (-1: none, or said).
struct Plot {
    pid_t pid = -1;
    std::string script_path, shown;
    int go = -1;
};

// Starts the script before its input is written, so that Python loads its
// packages (half a second or more of a processor) while the build goes on;
// at the lowest priority (nice 19), so that it takes mostly what the build
// leaves idle. (It keeps that priority to draw: an unprivileged process
// cannot raise it again.)
Plot start_plot(const std::string &script, const std::vector<std::string> &arguments, const std::string &shown) {
    Plot p{-1, plot_script(script), shown};
    int ends[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends) != 0) return p;
    std::vector<char *> argv{const_cast<char *>(plot_python()), const_cast<char *>(p.script_path.c_str()),
                             const_cast<char *>("--when-told")};
    for (const std::string &a : arguments) argv.push_back(const_cast<char *>(a.c_str()));
    argv.push_back(nullptr);
    p.pid = fork();
    if (p.pid == 0) {
        (void)setpriority(PRIO_PROCESS, 0, 19);  // this process only
        if (dup2(ends[1], STDIN_FILENO) < 0) _exit(127);
        execvp(plot_python(), argv.data());
        _exit(127);
    }
    close(ends[1]);
    if (p.pid > 0) p.go = ends[0];
    else close(ends[0]);
    return p;
}

// The plot's input is complete: it may draw. (MSG_NOSIGNAL: a script that
// already ended, without matplotlib say, must not take the build down.)
void tell_plot(Plot &p) {
    if (p.go < 0) return;
    (void)send(p.go, "go\n", 3, MSG_NOSIGNAL);
    close(p.go);
    p.go = -1;
}

// Stops and waits for a plot still running when the build fails, so that
// none outlives the command (finish_plot marks a plot it waited for).
struct PlotAwaited {
    std::optional<Plot> &plot;
    ~PlotAwaited() {
        if (!plot || plot->pid <= 0) return;
        if (plot->go >= 0) close(plot->go);  // not told: it ends without drawing
        kill(plot->pid, SIGTERM);
        waitpid(plot->pid, nullptr, 0);
    }
};

// Whether the picture was drawn; a warning on stderr when not. p is then
// waited for (pid 0).
bool finish_plot(Plot &p) {
    tell_plot(p);
    int status = -1;
    const bool started = p.pid > 0;
    if (started) waitpid(p.pid, &status, 0);
    p.pid = 0;
    if (started && WIFEXITED(status) && WEXITSTATUS(status) == 0) return true;
    // The script says why on stderr; the hint only where it applies (status
    // 3: a package missing; 127: no Python).
    const int code = started && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const char *hint = code == 3 ? "; are python3-matplotlib, python3-numpy and python3-netcdf4 installed?"
                       : code == 127 ? "; is python3 installed?"
                                     : "";
    std::fprintf(stderr, "unimesh build: warning: no %s (%s %s failed%s)\n", p.shown.c_str(), plot_python(),
                 p.script_path.c_str(), hint);
    return false;
}

void write_text(const std::string &path, const std::string &text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    f.flush();
    if (!f) throw Failure{"cannot write " + path};
}

// The map of the cells (none above kMapCellLimit cells, with a note),
// decided on the refined mesh's count (the optimisation changes it by a
// fraction of a percent).
std::optional<Plot> start_map(const BuildArgs &a, const std::string &mesh_nc, const std::string &png,
                              const std::string &shown, int64_t cells) {
    if (cells > kMapCellLimit) {
        std::fprintf(stderr, "unimesh build: note: no %s: about %lld cells, more than the map draws (%lld)\n",
                     shown.c_str(), static_cast<long long>(cells), static_cast<long long>(kMapCellLimit));
        return std::nullopt;
    }
    std::vector<std::string> arguments{mesh_nc, png};
    arguments.insert(arguments.end(), a.geometry.begin(), a.geometry.end());
    arguments.insert(arguments.end(), a.domain.begin(), a.domain.end());
    return start_plot("plot_mesh.py", arguments, shown);
}

}  // namespace

int run_build(const BuildArgs &a) {
    um_context *ctx = nullptr;
    um_spacing *h = nullptr;
    um_features *f = nullptr;
    um_options *opts = nullptr;
    um_mesh *m = nullptr;
    int rc = 0;
    std::string stage;
    try {
        if (a.components && a.mpas_format != "auto")
            throw Failure{"--mpas-format " + a.mpas_format +
                          " with --components: the component files are written in the automatic format only"};
        if (!a.spacing_file.empty()) {  // before any thread of ours exists: the probe forks
            const std::string refused = crash_reading_spacing_file(a.spacing_file, memory_cap_bytes(a.memory_cap),
                                                                   trial_read_seconds(a.spacing_file));
            if (!refused.empty()) throw Failure{"--spacing-file " + a.spacing_file + ": " + refused};
        }
        if (um_context_create(&ctx) != UM_OK) throw Failure{"cannot create a context"};
        check(um_context_set_threads(ctx, a.threads), ctx, "--threads");
        check(um_context_set_memory_cap(ctx, memory_cap_bytes(a.memory_cap)), ctx, "--memory-cap " + a.memory_cap);
        um_context_set_progress(ctx, report_progress, &stage);
        if (a.verbose) um_context_set_log(ctx, print_log, nullptr, UM_LOG_INFO);
        check(um_options_create(ctx, &opts), ctx, "options");
        // The case file's options and surface, then the flags': flags win.
        const bool surface_flag = a.surface_source == "--surface";
        if (!a.case_options.empty())
            check(um_options_set_string(opts, a.case_options.c_str()), ctx, "the case file's [options]");
        if (!surface_flag) set_surface(ctx, opts, a.surface, a.surface_source);
        if (!a.options.empty()) check(um_options_set_string(opts, a.options.c_str()), ctx, "--option");
        if (a.spacing_gradient_given)  // the library names a value out of range (or NaN)
            check(um_options_set_double(opts, UM_OPT_SPACING_GRADIENT, a.spacing_gradient), ctx, "--spacing-gradient");
        if (surface_flag) set_surface(ctx, opts, a.surface, a.surface_source);
        h = make_spacing(ctx, a);
        if (!a.geometry.empty() || !a.passages.empty() || !a.domain.empty()) {
            check(um_features_create(ctx, &f), ctx, "features");
            for (const auto &g : a.geometry)
                check(um_features_read_geojson(f, g.c_str(), nullptr, kind_code(a.default_kind)), ctx,
                      "--geometry " + g);
            for (const auto &p : a.passages) add_parts_of_kind(ctx, f, "--passages", p, UM_FEATURE_PASSAGE, "passage");
            for (const auto &d : a.domain) add_parts_of_kind(ctx, f, "--domain", d, UM_FEATURE_DOMAIN, "domain");
        }
        // Domain rings (from --domain or a --geometry file's "domain" kind) make the mesh regional.
        const bool regional = f && holds_domain(ctx, f);
        std::unique_ptr<OutputSet> out;
        try {
            out = std::make_unique<OutputSet>(a.out_dir);
        } catch (const std::runtime_error &e) {
            throw Failure{e.what()};
        }

        auto t0 = std::chrono::steady_clock::now();
        check(um_mesh_refine(ctx, h, f, opts, &m), ctx, "refinement");
        const auto t1 = std::chrono::steady_clock::now();
        const double refine_s = std::chrono::duration<double>(t1 - t0).count();
        const std::string dir = a.out_dir + "/";
        const std::string mesh_nc = out->staged("mesh.nc");
        // The pictures' scripts start now, at the lowest priority, and draw
        // once told their input (mesh.nc; quality.json) is written: Python
        // loads its packages mostly on what the mesh leaves idle.
        std::optional<Plot> map = start_map(a, mesh_nc, out->staged("mesh.png"), dir + "mesh.png", cell_count(m));
        const PlotAwaited map_awaited{map};
        std::optional<Plot> histograms = start_plot(
            "plot_quality.py", {out->staged("quality.json"), out->staged("quality.png")}, dir + "quality.png");
        const PlotAwaited histograms_awaited{histograms};
        // (The refined mesh's quality is printed from the optimised mesh's
        // report, which holds it: asked for here, its JSON would measure an
        // ellipsoid's geodesics once more, seconds at a million cells.)
        if (!a.no_optimise) check(um_mesh_optimise(m, opts), ctx, "optimisation");
        const double optimise_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        if (isatty(fileno(stderr))) std::fprintf(stderr, "\r%-60s\r", "");

        std::vector<std::string> written{"mesh.nc"}, not_written;
        // Seconds each output took, printed with the mesh's own timings.
        std::vector<std::pair<std::string, double>> took;
        auto lap = [&, last = std::chrono::steady_clock::now()](const std::string &what) mutable {
            const auto now = std::chrono::steady_clock::now();
            took.emplace_back(what, std::chrono::duration<double>(now - last).count());
            last = now;
        };
        if (a.components) {
            check(um_mesh_write_components(m, out->staging_directory().c_str()), ctx, "writing the components into " + dir);
            print_river_summary(out->staged("rivers.json"));
            lap("MPAS mesh and components");
        } else {
            const int32_t format = a.mpas_format == "netcdf4" ? UM_MPAS_FILE_NETCDF4 : UM_MPAS_FILE_AUTO;
            check(um_mesh_write_mpas_as(m, mesh_nc.c_str(), format), ctx, "writing " + dir + "mesh.nc");
            lap("MPAS mesh");
        }
        // A regional mesh's cells, read from mesh.nc (the library's counts are
        // the whole triangulation's; asking it would number the mesh again).
        size_t file_cells = 0;
        if (regional && !NcFile(mesh_nc).dim("nCells", &file_cells))
            throw Failure{"cannot read nCells back from " + dir + "mesh.nc"};
        if (map) tell_plot(*map);
        std::vector<std::string> &component_files = a.components ? written : not_written;
        component_files.insert(component_files.end(), kComponentFiles.begin(), kComponentFiles.end());
        std::string extra_error;
        if (!write_graph_info(mesh_nc, out->staged("graph.info"), &extra_error))
            throw Failure{extra_error};
        written.push_back("graph.info");
        lap("graph.info");
        if (a.vtu) {
            if (!write_cells_vtu(mesh_nc, out->staged("mesh.vtu"), &extra_error)) throw Failure{extra_error};
            if (!write_triangles_vtu(mesh_nc, out->staged("triangles.vtu"), &extra_error))
                throw Failure{extra_error};
            lap("VTU");
        }
        std::vector<std::string> &vtu_files = a.vtu ? written : not_written;
        vtu_files.insert(vtu_files.end(), {"mesh.vtu", "triangles.vtu"});
        if (a.jigsaw)
            check(um_mesh_write_jigsaw(m, out->staged("mesh.msh").c_str()), ctx, "writing " + dir + "mesh.msh");
        if (a.jigsaw) lap("mesh.msh");
        (a.jigsaw ? written : not_written).push_back("mesh.msh");
        const std::string quality = quality_json(ctx, m);
        write_text(out->staged("quality.json"), quality);
        written.push_back("quality.json");
        lap("quality.json");
        (finish_plot(*histograms) ? written : not_written).push_back("quality.png");
        (map && finish_plot(*map) ? written : not_written).push_back("mesh.png");
        lap("pictures");
        try {
            out->publish(written, not_written, mesh_file_id(mesh_nc));
        } catch (const std::runtime_error &e) {
            throw Failure{e.what()};
        }

        int64_t nv = 0, nt = 0, nr = 0, nf = 0;
        um_mesh_counts(m, &nv, &nt, &nr, &nf);
        std::string region;
        if (regional) {
            region = " (" + std::to_string(nv) + " with the cover outside the domain)";
            nv = static_cast<int64_t>(file_cells);
        }
        std::printf("mesh: %lld cells%s, %lld triangles, %lld restricted edges (%lld left coarser "
                    "than the features); refined in %.2f s, optimised in %.2f s\n",
                    (long long)nv, region.c_str(), (long long)nt, (long long)nr, (long long)nf, refine_s,
                    a.no_optimise ? 0.0 : optimise_s);
        if (!a.no_optimise) print_quality("refined", refined_report(quality));
        print_quality(a.no_optimise ? "refined" : "optimised", own_report(quality));
        std::string times;
        for (const auto &[what, seconds] : took) {
            char text[96];
            std::snprintf(text, sizeof text, "%s%s %.2f s", times.empty() ? "" : ", ", what.c_str(), seconds);
            times += text;
        }
        std::printf("outputs: %s\n", times.c_str());
        std::string files;
        for (const std::string &name : written) files += dir + name + ", ";
        std::printf("wrote %s%smanifest.json\n", files.c_str(), dir.c_str());
    } catch (const Failure &e) {
        if (isatty(fileno(stderr))) std::fprintf(stderr, "\r%-60s\r", "");
        std::fprintf(stderr, "unimesh build: %s\n", e.message.c_str());
        rc = 1;
    } catch (const std::exception &e) {  // the command line's own (out of memory): the scripts stopped on the way out
        std::fprintf(stderr, "unimesh build: %s\n", e.what());
        rc = 1;
    }
    um_mesh_destroy(m);
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_options_destroy(opts);
    um_context_destroy(ctx);
    return rc;
}
