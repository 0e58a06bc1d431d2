// bench_refine: times the whole pipeline, refinement (um_mesh_refine:
// boundary refinement along the features, then surface refinement) and the
// weighted optimisation (um_mesh_optimise), on the three cases of the issues
// "Geometry, spacing functions and restricted refinement" and "Weighted
// primal-dual optimisation", with 1 and 2 threads, printing cells, time per
// phase, peak memory and the quality metrics before and after optimising
// (--no-optimise: refinement only; --log: the library's log lines of level
// info and above go to stderr; --options "name=value;...": options for both
// calls, as um_options_set_string reads them; --floors 0,0.7: each case at
// each time-step floor, side by side, to show what the floor costs the
// coastline's fidelity).
//
//   (a) uniform 30 km, global, no features;
//   (b) coast_global_l + rivers_global_l at 60 km;
//   (c) the Mid-Atlantic unified case: the spacing midatlantic_cellwidth.nc,
//       coast_global_l outside the Mid-Atlantic box and the full-resolution
//       coast and rivers inside it.
//
// Each run happens in a fork()ed child (peak memory per run: the child's max
// RSS growth over the refinement, read with getrusage). Phase times come from
// the progress callback's stage names. Data: the repository's data/ folder.
#include <array>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "unimesh.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Quality {
    double qt_min = 0, qp_min = 0, angle_max = 0, obtuse_pct = 0;
    int64_t not_well_centred = 0, not_well_centred_off_gamma = 0;
    // The time-step floor: least dcEdge/h over the ocean mesh's edges and
    // how many are below the floor the mesh was built to.
    double ocean_min = 0, floor = 0;
    int64_t below_floor = 0, closed_passages = 0;
    // How closely the mesh follows the closed coastlines: their restricted
    // edges, mean eps / (beta h), and how many are beyond beta h.
    int64_t coast_edges = 0, beyond_beta = 0;
    double eps_mean = 0;
};

// Edge lengths of the refined mesh over h at their midpoints (the
// refinement stage's own criterion: issue "every edge within [0.75, 1.35] h").
struct EdgeRatios {
    double min = 0, max = 0, share_below = 0, share_above = 0;  // shares in %
};

struct Result {
    double total_s = 0, boundary_s = 0, surface_s = 0, relax_s = 0, tags_s = 0, optimise_s = 0;
    // The surface passes' points, and how many of them territories placed
    // in parallel (from the library's debug line "refine surface: ...").
    long long surface_points = 0, by_territories = 0;
    EdgeRatios edges;
    int has_edges = 0;
    int64_t obtuse = 0, obtuse_on_gamma = 0, obtuse_all_gamma = 0, obtuse_forced = 0;  // of the final mesh (count_obtuse)
    Quality before, after;
    int64_t cells = 0, triangles = 0, restricted = 0, filtered = 0;
    double peak_mb = 0;
    int ok = 0;
    char error[200] = {0};
};

bool g_log = false;          // --log
std::string g_options;  // --options (and the floor of --floors): um_options_set_string assignments for both calls

// Phase timing through the progress callback: time spent since the first
// report of a stage until the first report of the next one.
struct Phases {
    Clock::time_point start, last;
    std::string stage;
    std::map<std::string, double> seconds;
};

int32_t on_progress(void *user, const char *stage, double) {
    auto *p = static_cast<Phases *>(user);
    auto now = Clock::now();
    if (p->stage != stage) {
        if (!p->stage.empty()) p->seconds[p->stage] += std::chrono::duration<double>(now - p->last).count();
        p->stage = stage;
        p->last = now;
    }
    return 0;
}

// The number after `key` at or after `from` in the report text.
double number_after(const std::string &text, size_t from, const std::string &key) {
    size_t at = text.find(key, from);
    return at == std::string::npos ? -1 : std::strtod(text.c_str() + at + key.size(), nullptr);
}

// The headline metrics of a quality report (um_mesh_quality_json), from the
// object that starts at `from`.
Quality quality_in(const std::string &json, size_t from) {
    Quality q;
    q.qt_min = number_after(json, json.find("\"area_length_ratio\"", from), "\"min\": ");
    q.qp_min = number_after(json, json.find("\"primal_dual\"", from), "\"min\": ");
    q.angle_max = number_after(json, json.find("\"angle_max_deg\"", from), "\"max\": ");
    const double triangles = number_after(json, from, "\"triangles\": ");
    q.obtuse_pct = 100.0 * number_after(json, from, "\"obtuse_triangles\": ") / triangles;
    q.not_well_centred = static_cast<int64_t>(number_after(json, from, "\"not_well_centred\": "));
    q.not_well_centred_off_gamma = static_cast<int64_t>(number_after(json, from, "\"not_well_centred_off_gamma\": "));
    const size_t ocean = json.find("\"ocean_floor\"", from);
    q.floor = number_after(json, ocean, "\"floor\": ");
    q.ocean_min = number_after(json, ocean, "\"min_ratio\": ");
    q.below_floor = static_cast<int64_t>(number_after(json, ocean, "\"below_floor\": "));
    q.closed_passages = static_cast<int64_t>(number_after(json, ocean, "\"closed_passages\": {\"count\": "));
    const size_t coast = json.find("\"coastline_fidelity\"", from);
    if (coast != std::string::npos && coast < json.find("\"before_optimisation\"", from)) {
        q.coast_edges = static_cast<int64_t>(number_after(json, coast, "\"restricted_edges\": "));
        q.eps_mean = number_after(json, coast, "\"mean\": ");
        q.beyond_beta = static_cast<int64_t>(number_after(json, coast, "\"beyond_beta\": "));
    }
    return q;
}

std::string quality_json(um_mesh *m) {
    int64_t needed = 0;
    um_mesh_quality_json(m, nullptr, 0, &needed);
    std::string text(static_cast<size_t>(needed), '\0');
    um_mesh_quality_json(m, text.data(), needed, nullptr);
    return text;
}

void check(um_status s, um_context *ctx, const char *what) {
    if (s != UM_OK) {
        std::fprintf(stderr, "bench_refine: %s: %s\n", what, um_context_last_error(ctx));
        std::exit(2);
    }
}

// coast_global_l with the segments inside the Mid-Atlantic box removed: each
// part is split where it enters the box (open parts).
void add_global_coast_outside_box(um_context *ctx, um_features *dst, const std::string &path) {
    um_features *all = nullptr;
    check(um_features_create(ctx, &all), ctx, "features");
    check(um_features_read_geojson(all, path.c_str(), nullptr, 0), ctx, path.c_str());
    int64_t np = 0, npt = 0, nseg = 0;
    um_features_counts(all, &np, &npt, &nseg);
    std::vector<double> lon(npt), lat(npt);
    std::vector<int64_t> off(np + 1);
    std::vector<int32_t> closed(np), kind(np), ids(np);
    check(um_features_copy_points(all, lon.data(), lat.data(), npt), ctx, "copy points");
    check(um_features_copy_parts(all, off.data(), closed.data(), kind.data(), ids.data(), np + 1), ctx,
          "copy parts");
    auto inside = [&](int64_t i) {
        return lon[i] > -78.5 && lon[i] < -73.5 && lat[i] > 36.5 && lat[i] < 41.0;
    };
    std::vector<double> olon, olat;
    std::vector<int64_t> ooff = {0};
    std::vector<int32_t> oclosed, okind;
    for (int64_t p = 0; p < np; ++p) {
        bool any_inside = false;
        for (int64_t i = off[p]; i < off[p + 1]; ++i) any_inside |= inside(i);
        auto flush = [&](int32_t k, int32_t c) {
            if (static_cast<int64_t>(olon.size()) - ooff.back() >= 2) {
                ooff.push_back(static_cast<int64_t>(olon.size()));
                oclosed.push_back(c), okind.push_back(k);
            } else {
                olon.resize(ooff.back()), olat.resize(ooff.back());
            }
        };
        if (!any_inside) {
            for (int64_t i = off[p]; i < off[p + 1]; ++i) olon.push_back(lon[i]), olat.push_back(lat[i]);
            flush(kind[p], closed[p]);
            continue;
        }
        for (int64_t i = off[p]; i < off[p + 1]; ++i) {
            if (inside(i)) {
                flush(kind[p], 0);
                continue;
            }
            olon.push_back(lon[i]), olat.push_back(lat[i]);
        }
        flush(kind[p], 0);
    }
    int64_t n_parts = static_cast<int64_t>(oclosed.size());
    check(um_features_add(dst, static_cast<int64_t>(olon.size()), olon.data(), olat.data(), n_parts,
                          ooff.data(), oclosed.data(), okind.data(), nullptr),
          ctx, "add clipped coast");
    um_features_destroy(all);
}

// The mesh as the C API hands it out: unit vectors, triangles, parts.
struct MeshCopy {
    std::vector<std::array<double, 3>> x;
    std::vector<int32_t> tri, part;  // part: -1 off Gamma
};

bool copy_mesh(const um_mesh *m, MeshCopy *out) {
    constexpr double kDeg = M_PI / 180;
    int64_t nv = 0, nt = 0;
    if (um_mesh_counts(m, &nv, &nt, nullptr, nullptr) != UM_OK) return false;
    std::vector<double> lon(nv), lat(nv);
    out->tri.resize(3 * nt), out->part.resize(nv);
    if (um_mesh_copy_vertices(m, lon.data(), lat.data(), nv) != UM_OK ||
        um_mesh_copy_triangles(m, 0, out->tri.data(), 3 * nt) != UM_OK ||
        um_mesh_copy_vertex_parts(m, 0, out->part.data(), nv) != UM_OK)
        return false;
    out->x.resize(nv);
    for (int64_t v = 0; v < nv; ++v)
        out->x[v] = {std::cos(lat[v] * kDeg) * std::cos(lon[v] * kDeg),
                     std::cos(lat[v] * kDeg) * std::sin(lon[v] * kDeg), std::sin(lat[v] * kDeg)};
    return true;
}

std::array<double, 3> cross(const std::array<double, 3> &a, const std::array<double, 3> &b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const std::array<double, 3> &a, const std::array<double, 3> &b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Triangles with an angle over 90 degrees (between the great arcs at each
// corner), and how many of them have two or three vertices on Gamma.
// Obtuse triangles of the final mesh: all, those with 2 or 3 vertices on
// Gamma, and the forced ones: two vertices on Gamma, the obtuse corner at
// one of them, B, whose only vertex off Gamma on that side is the
// triangle's third (the triangle across that spoke has its far vertex on
// Gamma too). B's two triangles there share its 180 degrees, so one angle is
// at least 90 whatever the positions.
void count_obtuse(const MeshCopy &c, int64_t *obtuse, int64_t *on_gamma, int64_t *all_gamma, int64_t *forced) {
    *obtuse = *on_gamma = *all_gamma = *forced = 0;
    const size_t nt = c.tri.size() / 3;
    // The triangles at each vertex (compressed rows).
    std::vector<int32_t> first(c.x.size() + 1, 0), at(c.tri.size());
    for (int32_t v : c.tri) ++first[v + 1];
    for (size_t v = 0; v < c.x.size(); ++v) first[v + 1] += first[v];
    std::vector<int32_t> fill(first.begin(), first.end() - 1);
    for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) at[fill[c.tri[3 * t + k]]++] = static_cast<int32_t>(t);
    auto on = [&](int32_t v) { return c.part[v] >= 0; };
    for (size_t t = 0; t < nt; ++t) {
        int obtuse_at = -1, n_gamma = 0;
        for (int k = 0; k < 3; ++k) {
            const auto &a = c.x[c.tri[3 * t + k]], &b = c.x[c.tri[3 * t + (k + 1) % 3]],
                       &d = c.x[c.tri[3 * t + (k + 2) % 3]];
            std::array<double, 3> tb, td;  // the arcs' tangents at a
            for (int i = 0; i < 3; ++i) tb[i] = b[i] - dot(a, b) * a[i], td[i] = d[i] - dot(a, d) * a[i];
            if (dot(tb, td) < 0) obtuse_at = k;
            n_gamma += on(c.tri[3 * t + k]);
        }
        if (obtuse_at < 0) continue;
        ++*obtuse, *on_gamma += n_gamma >= 2, *all_gamma += n_gamma == 3;
        const int32_t b = c.tri[3 * t + obtuse_at], x = c.tri[3 * t + (obtuse_at + 1) % 3],
                      y = c.tri[3 * t + (obtuse_at + 2) % 3];
        if (n_gamma != 2 || !on(b)) continue;
        const int32_t off = on(x) ? y : x;  // the spoke of b off Gamma
        for (int32_t i = first[b]; i < first[b + 1]; ++i) {
            const int32_t u = at[i];
            if (static_cast<size_t>(u) == t) continue;
            const int32_t *w = &c.tri[3 * static_cast<size_t>(u)];
            if (w[0] != off && w[1] != off && w[2] != off) continue;
            const int32_t far = w[0] != b && w[0] != off ? w[0] : (w[1] != b && w[1] != off ? w[1] : w[2]);
            *forced += on(far);
        }
    }
}

// False (and nothing measured) when the spacing fails.
bool edge_ratios(const MeshCopy &c, const um_spacing *h, EdgeRatios *out) {
    constexpr double kRadiusKm = 6371.22, kDeg = M_PI / 180;  // the default sphere
    const std::vector<int32_t> &tri = c.tri;
    auto unit = [&](int32_t v) { return c.x[v]; };
    const int64_t nt = static_cast<int64_t>(tri.size() / 3);
    std::vector<double> length_km, mid_lon, mid_lat;
    for (int64_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const int32_t a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3];
            if (a > b) continue;  // each edge once: it runs b -> a in the other triangle
            const auto x = unit(a), y = unit(b);
            const std::array<double, 3> n = cross(x, y);
            length_km.push_back(kRadiusKm * std::atan2(std::sqrt(dot(n, n)), dot(x, y)));
            const double mx = x[0] + y[0], my = x[1] + y[1], mz = x[2] + y[2];
            mid_lon.push_back(std::atan2(my, mx) / kDeg);
            mid_lat.push_back(std::atan2(mz, std::sqrt(mx * mx + my * my)) / kDeg);
        }
    std::vector<double> h_km(length_km.size());
    if (um_spacing_evaluate(h, static_cast<int64_t>(h_km.size()), mid_lon.data(), mid_lat.data(),
                            h_km.data()) != UM_OK)
        return false;
    EdgeRatios &r = *out;
    r.min = 1e300, r.max = 0;
    int64_t below = 0, above = 0;
    for (size_t i = 0; i < h_km.size(); ++i) {
        const double q = length_km[i] / h_km[i];
        r.min = std::min(r.min, q), r.max = std::max(r.max, q);
        below += q < 0.75, above += q > 1.35;
    }
    const double n = std::max<double>(1, double(h_km.size()));
    r.share_below = 100.0 * double(below) / n, r.share_above = 100.0 * double(above) / n;
    return true;
}

Result run_case(const std::string &name, const std::string &data, int threads, bool optimise) {
    Result r;
    um_context *ctx = nullptr;
    um_context_create(&ctx);
    um_context_set_threads(ctx, threads);
    um_spacing *h = nullptr;
    um_features *f = nullptr;
    if (name == "uniform-30km") {
        check(um_spacing_create_constant(ctx, 30.0, &h), ctx, "spacing");
    } else if (name == "coast-rivers-60km") {
        check(um_spacing_create_constant(ctx, 60.0, &h), ctx, "spacing");
        check(um_features_create(ctx, &f), ctx, "features");
        check(um_features_read_geojson(f, (data + "/coast_global_l.geojson").c_str(), nullptr, 0), ctx, "coast");
        check(um_features_read_geojson(f, (data + "/rivers_global_l.geojson").c_str(), nullptr, 0), ctx, "rivers");
    } else {
        check(um_spacing_create_from_file(ctx, (data + "/midatlantic_cellwidth.nc").c_str(), &h), ctx, "spacing file");
        check(um_features_create(ctx, &f), ctx, "features");
        add_global_coast_outside_box(ctx, f, data + "/coast_global_l.geojson");
        check(um_features_read_geojson(f, (data + "/coast_midatlantic_f.geojson").c_str(), nullptr, 0), ctx, "coast f");
        check(um_features_read_geojson(f, (data + "/rivers_midatlantic_f.geojson").c_str(), nullptr, 0), ctx, "rivers f");
    }
    Phases phases;
    um_context_set_progress(ctx, on_progress, &phases);
    um_context_set_log(ctx, [](void *user, int32_t level, const char *msg) {
        auto *x = static_cast<Result *>(user);
        long long points = 0, parallel = 0;
        if (std::sscanf(msg, "refine surface: %lld points, %lld of them by territories", &points, &parallel) == 2)
            x->surface_points += points, x->by_territories += parallel;
        if (g_log && level >= UM_LOG_INFO) std::fprintf(stderr, "  log: %s\n", msg);
    }, &r, UM_LOG_DEBUG);
    long base_kb = bench::usage_now().maxrss_kb;
    auto t0 = Clock::now();
    phases.start = phases.last = t0;
    um_mesh *m = nullptr;
    um_options *opts = nullptr;
    check(um_options_create(ctx, &opts), ctx, "options");
    check(um_options_set_string(opts, g_options.c_str()), ctx, "--options");
    um_status s = um_mesh_refine(ctx, h, f, opts, &m);
    auto t1 = Clock::now();
    double refine_s = std::chrono::duration<double>(t1 - t0).count();
    if (!phases.stage.empty()) phases.seconds[phases.stage] += std::chrono::duration<double>(t1 - phases.last).count();
    r.boundary_s = phases.seconds["refine boundary"];
    r.relax_s = phases.seconds["refine relax"];
    r.tags_s = phases.seconds["refine tags"];
    r.surface_s = refine_s - r.boundary_s - r.relax_s - r.tags_s;
    if (s == UM_OK && optimise) {
        um_context_set_progress(ctx, nullptr, nullptr);
        auto t2 = Clock::now();
        s = um_mesh_optimise(m, opts);
        r.optimise_s = std::chrono::duration<double>(Clock::now() - t2).count();
    }
    r.total_s = refine_s + r.optimise_s;
    // Peak memory of the pipeline itself: read before the report is made.
    r.peak_mb = (bench::usage_now().maxrss_kb - base_kb) / 1024.0;
    if (s != UM_OK) {
        std::snprintf(r.error, sizeof r.error, "%s", um_context_last_error(ctx));
    } else {
        um_mesh_counts(m, &r.cells, &r.triangles, &r.restricted, &r.filtered);
        // After the peak was read (the copies would be part of it).
        MeshCopy copy;
        if (copy_mesh(m, &copy)) {
            count_obtuse(copy, &r.obtuse, &r.obtuse_on_gamma, &r.obtuse_all_gamma, &r.obtuse_forced);
            r.has_edges = edge_ratios(copy, h, &r.edges);
        }
        const std::string json = quality_json(m);
        r.after = quality_in(json, 0);
        const size_t before = json.find("\"before_optimisation\"");
        r.before = before == std::string::npos ? r.after : quality_in(json, before);
        r.ok = 1;
    }
    um_mesh_destroy(m);
    um_options_destroy(opts);
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_context_destroy(ctx);
    return r;
}

Result in_child(const std::string &name, const std::string &data, int threads, bool optimise) {
    Result r;
    int status = 0;
    auto work = [&] { return run_case(name, data, threads, optimise); };
    if (bench::run_in_child(work, r, 0.0, &status) != bench::ChildOutcome::ok) {
        r = Result();
        std::snprintf(r.error, sizeof r.error, "child failed (status %d)", status);
    }
    return r;
}

// "a,b,c" -> {"a", "b", "c"} (empty items dropped).
std::vector<std::string> comma_list(const std::string &list) {
    std::vector<std::string> items;
    for (size_t b = 0, e; b <= list.size(); b = e + 1) {
        e = list.find(',', b);
        if (e == std::string::npos) e = list.size();
        if (e > b) items.push_back(list.substr(b, e - b));
    }
    return items;
}

}  // namespace

int main(int argc, char **argv) {
    std::string data = UNIMESH_DATA_DIR;
    std::vector<std::string> cases = {"uniform-30km", "coast-rivers-60km", "midatlantic"};
    std::vector<int> thread_counts = {1, 2};
    std::vector<std::string> floors = {""};  // "": the options' (or the default) floor
    bool optimise = true;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--data") && i + 1 < argc) data = argv[++i];
        else if (!std::strcmp(argv[i], "--no-optimise")) optimise = false;
        else if (!std::strcmp(argv[i], "--log")) g_log = true;
        else if (!std::strcmp(argv[i], "--options") && i + 1 < argc) g_options = argv[++i];
        else if (!std::strcmp(argv[i], "--floors") && i + 1 < argc) floors = comma_list(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
            thread_counts.clear();
            for (const char *p = argv[++i]; *p;) {
                char *end = nullptr;
                long t = std::strtol(p, &end, 10);
                if (end == p || t < 1) { std::fprintf(stderr, "bench_refine: bad --threads\n"); return 2; }
                thread_counts.push_back(static_cast<int>(t));
                p = *end == ',' ? end + 1 : end;
            }
        }
        else if (!std::strcmp(argv[i], "--cases") && i + 1 < argc) {
            cases = comma_list(argv[++i]);
            for (const auto &c : cases)
                if (c != "uniform-30km" && c != "coast-rivers-60km" && c != "midatlantic") {
                    std::fprintf(stderr, "bench_refine: --cases: no case '%s'\n", c.c_str());
                    return 2;
                }
        } else {
            std::fprintf(stderr, "usage: bench_refine [--cases uniform-30km,coast-rivers-60km,midatlantic] "
                                 "[--threads 1,2] [--no-optimise] [--log] [--options \"name=value;...\"] [--floors 0,0.7] "
                                 "[--data DIR]\n");
            return 2;
        }
    }
    std::printf("# bench_refine: um_mesh_refine%s, unimesh %s\n", optimise ? " + um_mesh_optimise" : "",
                um_version_string());
    std::printf("# each run in its own child; peak_MB = growth of its max RSS during refine + optimise\n"
                "# (the quality report is read afterwards; the optimisation's own report of the\n"
                "# refined mesh is part of it)\n");
    std::printf("%-18s %3s %8s %8s %8s %8s %6s %6s %6s %8s %8s %8s %7s  %-40s  %-40s  %-32s  %s\n", "case", "thr",
                "cells", "restrict", "boundary", "surface", "par%", "relax", "tags", "optimise", "total_s", "peak_MB", "B/cell",
                "before: QTmin QPmin maxang obt% nwc/off", "after: QTmin QPmin maxang obt% nwc/off",
                "final l/h: min max <0.75% >1.35%",
                "obtuse on-Gamma% all-Gamma% forced%  ocean: floor min below closed  coast: edges eps/bh >bh");
    int failures = 0;
    auto quality_text = [](const Quality &q) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.3f %.3f %6.1f %6.3f %5lld/%lld", q.qt_min, q.qp_min, q.angle_max,
                      q.obtuse_pct, (long long)q.not_well_centred, (long long)q.not_well_centred_off_gamma);
        return std::string(buf);
    };
    const std::string options = g_options;
    for (const auto &c : cases)
        for (const std::string &floor : floors)
        for (int threads : thread_counts) {
            g_options = floor.empty() ? options : options + (options.empty() ? "" : ";") + "ocean_floor=" + floor;
            Result r = in_child(c, data, threads, optimise);
            if (!r.ok) {
                std::printf("%-18s %3d FAILED: %s\n", c.c_str(), threads, r.error);
                ++failures;
                continue;
            }
            char edges[64] = "-";
            if (r.has_edges)
                std::snprintf(edges, sizeof edges, "%.3f %.3f %6.2f %6.2f", r.edges.min, r.edges.max,
                              r.edges.share_below, r.edges.share_above);
            std::printf("%-18s %3d %8lld %8lld %8.3f %8.3f %6.1f %6.3f %6.3f %8.3f %8.3f %8.1f %7.0f  %-40s  %-40s  "
                        "%-32s  %lld %.1f %.1f %.1f  %.2f %.3f %lld %lld  %lld %.3f %lld\n",
                        c.c_str(), threads, (long long)r.cells, (long long)r.restricted, r.boundary_s,
                        r.surface_s, r.surface_points > 0 ? 100.0 * double(r.by_territories) / double(r.surface_points) : 0.0,
                        r.relax_s, r.tags_s, r.optimise_s, r.total_s, r.peak_mb,
                        r.peak_mb * 1048576.0 / double(r.cells), quality_text(r.before).c_str(),
                        quality_text(r.after).c_str(), edges, (long long)r.obtuse,
                        r.obtuse > 0 ? 100.0 * double(r.obtuse_on_gamma) / double(r.obtuse) : 0.0,
                        r.obtuse > 0 ? 100.0 * double(r.obtuse_all_gamma) / double(r.obtuse) : 0.0,
                        r.obtuse > 0 ? 100.0 * double(r.obtuse_forced) / double(r.obtuse) : 0.0, r.after.floor,
                        r.after.ocean_min, (long long)r.after.below_floor, (long long)r.after.closed_passages,
                        (long long)r.after.coast_edges, r.after.eps_mean, (long long)r.after.beyond_beta);
            std::fflush(stdout);
        }
    std::printf("# boundary = boundary refinement; surface = surface refinement; par%% = share of the\n"
                "# surface points placed by territories in parallel; relax = the edge-length relaxation;\n"
                "# tags = Tri|Gamma, sides, numbering;\n"
                "# final l/h = edge length over h at its midpoint, of the final mesh (refined, or optimised)\n"
                "# obtuse on-Gamma%% all-Gamma%% forced%% = obtuse triangles of the final mesh, the share of them with\n"
                "# 2 or 3 vertices on Gamma, with 3, and the share forced by a Gamma vertex with one vertex off Gamma on that\n"
                "# side (its two triangles there share 180 degrees)\n"
                "# QT = area-length ratio, QP = primal-dual, obt%% = %% of triangles with an angle > 90,\n"
                "# nwc/off = triangles not containing their orthocentre / those of them with a vertex off Gamma\n"
                "# ocean: the ocean_floor option, the least dcEdge/h over the edges between two cells of the ocean\n"
                "# mesh, how many of them are below the floor, and the passages the mesh closed\n"
                "# coast: the restricted edges on closed coastlines, their mean eps/(beta h) (eps: the distance from\n"
                "# the edge's midpoint to the coastline) and how many are beyond beta h\n");
    return failures ? 1 : 0;
}
