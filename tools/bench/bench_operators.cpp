// bench_operators: how accurate the MPAS operators are on unimesh's meshes,
// against the icosahedral grid of the same size (and any MPAS mesh file).
//
// For each mesh: the standard TRSK C-grid operators (mpas_operators.hpp) on
// closed-form fields - gradient, divergence, curl, TRSK tangential
// reconstruction, kinetic energy - as relative area-weighted L2 and Linf
// errors, the observed orders between the meshes of one family, and the mesh
// diagnostics that drive them (centroid offset, the two edge offsets,
// dcEdge/h, Q^T, 5-7 defects).
//
//   bench_operators [--cases LIST] [--threads N] [--options "k=v;..."] [--validate]
//
// Cases: ico-<level> (the icosahedral bisection grid's Voronoi mesh, built by
// the engine), uniform-<km> (um_mesh_refine + um_mesh_optimise at a constant
// spacing, arrays copied out through the C API), coast-rivers-<km> (the same
// with data/coast_global_l and rivers_global_l; its errors also next to and
// away from the features), file:<path> (an MPAS mesh file, e.g. another
// generator's). --validate: exit 1 unless the ico-6 row matches the reference
// figures of the operator definitions (within 12 %), which checks the
// operators themselves.
#include <netcdf.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "dual/mpas_mesh.hpp"
#include "mpas_operators.hpp"
#include "point_sets.hpp"
#include "tri/triangulation.hpp"
#include "unimesh.h"

namespace {

using bench::MpasArrays;
using bench::V3;
using Clock = std::chrono::steady_clock;

[[noreturn]] void die(const std::string &what) {
    std::fprintf(stderr, "bench_operators: %s\n", what.c_str());
    std::exit(2);
}

// ------------------------------------------------------------ mesh sources

// The icosahedral grid's Voronoi mesh (weights 0) on the unit sphere.
MpasArrays icosahedral_mesh(int level) {
    std::vector<double> xyz;
    std::string error;
    if (!bench::icosahedral_points(level, xyz, error)) die(error);
    um::Context ctx;
    um::tri::Triangulation tri;
    tri.build(ctx, static_cast<int64_t>(xyz.size() / 3),
              [&](int64_t i) { return um::geom::Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }, nullptr);
    um::dual::MpasMeshInput input;
    input.radius_m = 1;
    const um::dual::MpasMesh d = um::dual::build_mpas_mesh(ctx, tri, input);
    MpasArrays m;
    m.n_cells = d.n_cells, m.n_edges = d.n_edges, m.n_vertices = d.n_vertices, m.max_edges = d.max_edges;
    for (int32_t i = 0; i < d.n_cells; ++i) m.x_cell.push_back({d.x_cell[i], d.y_cell[i], d.z_cell[i]});
    for (int32_t i = 0; i < d.n_edges; ++i) m.x_edge.push_back({d.x_edge[i], d.y_edge[i], d.z_edge[i]});
    for (int32_t i = 0; i < d.n_vertices; ++i) m.x_vertex.push_back({d.x_vertex[i], d.y_vertex[i], d.z_vertex[i]});
    m.n_edges_on_cell = d.n_edges_on_cell, m.edges_on_cell = d.edges_on_cell, m.vertices_on_cell = d.vertices_on_cell;
    m.cells_on_edge = d.cells_on_edge, m.vertices_on_edge = d.vertices_on_edge;
    m.n_edges_on_edge = d.n_edges_on_edge, m.edges_on_edge = d.edges_on_edge, m.weights_on_edge = d.weights_on_edge;
    m.cells_on_vertex = d.cells_on_vertex, m.edges_on_vertex = d.edges_on_vertex;
    m.area_cell = d.area_cell, m.area_triangle = d.area_triangle, m.dc_edge = d.dc_edge, m.dv_edge = d.dv_edge;
    return m;
}

// Reads named variables of an MPAS mesh, from the library or from a file,
// into the unit-sphere arrays (0-based connectivity).
class MpasSource {
public:
    virtual ~MpasSource() = default;
    virtual void dimensions(int64_t &cells, int64_t &edges, int64_t &vertices, int64_t &max_edges) = 0;
    virtual std::vector<double> real(const char *name, int64_t count) = 0;
    virtual std::vector<int32_t> index(const char *name, int64_t count) = 0;  // 0-based, -1 padding
    virtual std::vector<int32_t> integer(const char *name, int64_t count) = 0;
    virtual bool has(const char *name) = 0;
};

class LibrarySource : public MpasSource {
public:
    explicit LibrarySource(const um_mesh *m) : m_(m) {}
    void dimensions(int64_t &c, int64_t &e, int64_t &v, int64_t &me) override {
        if (um_mesh_mpas_dimensions(m_, &c, &e, &v, &me) != UM_OK) die("um_mesh_mpas_dimensions failed");
    }
    std::vector<double> real(const char *name, int64_t n) override {
        std::vector<double> out(static_cast<size_t>(n));
        if (um_mesh_copy_mpas_real(m_, name, out.data(), n) != UM_OK) die(std::string("copy of ") + name);
        return out;
    }
    std::vector<int32_t> index(const char *name, int64_t n) override {
        std::vector<int32_t> out(static_cast<size_t>(n));
        if (um_mesh_copy_mpas_int(m_, name, 0, out.data(), n) != UM_OK) die(std::string("copy of ") + name);
        return out;
    }
    std::vector<int32_t> integer(const char *name, int64_t n) override { return index(name, n); }
    bool has(const char *name) override {
        int32_t type;
        int64_t rows, cols;
        return um_mesh_mpas_variable(m_, name, &type, &rows, &cols) == UM_OK;
    }

private:
    const um_mesh *m_;
};

class FileSource : public MpasSource {
public:
    explicit FileSource(const std::string &path) : path_(path) {
        if (nc_open(path.c_str(), NC_NOWRITE, &id_) != NC_NOERR) die("cannot open " + path);
    }
    ~FileSource() override { nc_close(id_); }
    void dimensions(int64_t &c, int64_t &e, int64_t &v, int64_t &me) override {
        c = dim("nCells"), e = dim("nEdges"), v = dim("nVertices"), me = dim("maxEdges");
    }
    std::vector<double> real(const char *name, int64_t n) override { return read<double>(name, n, nc_get_var_double); }
    std::vector<int32_t> integer(const char *name, int64_t n) override { return read<int32_t>(name, n, nc_get_var_int); }
    std::vector<int32_t> index(const char *name, int64_t n) override {
        std::vector<int32_t> out = integer(name, n);
        for (int32_t &i : out) --i;
        return out;
    }
    bool has(const char *name) override {
        int var;
        return nc_inq_varid(id_, name, &var) == NC_NOERR;
    }

private:
    // The whole variable `name`, which must hold n values, through get (nc_get_var_<type>).
    template <class T, class Get>
    std::vector<T> read(const char *name, int64_t n, Get get) {
        std::vector<T> out(static_cast<size_t>(n));
        int var;
        if (nc_inq_varid(id_, name, &var) != NC_NOERR || size_of(var) != n || get(id_, var, out.data()) != NC_NOERR)
            die(path_ + ": variable " + name + " missing or of the wrong size");
        return out;
    }
    int64_t dim(const char *name) {
        int d;
        size_t len;
        if (nc_inq_dimid(id_, name, &d) != NC_NOERR || nc_inq_dimlen(id_, d, &len) != NC_NOERR)
            die(path_ + ": no dimension " + name);
        return static_cast<int64_t>(len);
    }
    int64_t size_of(int var) {
        int nd, dims[NC_MAX_VAR_DIMS];
        nc_inq_varndims(id_, var, &nd);
        nc_inq_vardimid(id_, var, dims);
        int64_t n = 1;
        for (int k = 0; k < nd; ++k) {
            size_t len;
            nc_inq_dimlen(id_, dims[k], &len);
            n *= static_cast<int64_t>(len);
        }
        return n;
    }
    std::string path_;
    int id_ = -1;
};

// The unit vectors of positions (x, y, z) in metres, and the length of the
// first (the sphere's radius) in *radius when asked.
std::vector<V3> points(MpasSource &s, const char *x, const char *y, const char *z, int64_t n,
                       double *radius = nullptr) {
    const std::vector<double> a = s.real(x, n), b = s.real(y, n), c = s.real(z, n);
    std::vector<V3> p(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) p[i] = bench::unit({a[i], b[i], c[i]});
    if (radius) *radius = bench::norm({a[0], b[0], c[0]});
    return p;
}

MpasArrays read_mesh(MpasSource &s) {
    MpasArrays m;
    s.dimensions(m.n_cells, m.n_edges, m.n_vertices, m.max_edges);
    double r = 0;
    m.x_cell = points(s, "xCell", "yCell", "zCell", m.n_cells, &r);
    m.x_edge = points(s, "xEdge", "yEdge", "zEdge", m.n_edges);
    m.x_vertex = points(s, "xVertex", "yVertex", "zVertex", m.n_vertices);
    const int64_t me = m.max_edges;
    m.n_edges_on_cell = s.integer("nEdgesOnCell", m.n_cells);
    m.edges_on_cell = s.index("edgesOnCell", m.n_cells * me);
    m.vertices_on_cell = s.index("verticesOnCell", m.n_cells * me);
    m.cells_on_edge = s.index("cellsOnEdge", 2 * m.n_edges);
    m.vertices_on_edge = s.index("verticesOnEdge", 2 * m.n_edges);
    m.n_edges_on_edge = s.integer("nEdgesOnEdge", m.n_edges);
    m.edges_on_edge = s.index("edgesOnEdge", 2 * me * m.n_edges);
    m.weights_on_edge = s.real("weightsOnEdge", 2 * me * m.n_edges);
    m.cells_on_vertex = s.index("cellsOnVertex", 3 * m.n_vertices);
    m.edges_on_vertex = s.index("edgesOnVertex", 3 * m.n_vertices);
    m.area_cell = s.real("areaCell", m.n_cells);
    m.area_triangle = s.real("areaTriangle", m.n_vertices);
    m.dc_edge = s.real("dcEdge", m.n_edges);
    m.dv_edge = s.real("dvEdge", m.n_edges);
    for (double &a : m.area_cell) a /= r * r;
    for (double &a : m.area_triangle) a /= r * r;
    for (double &l : m.dc_edge) l /= r;
    for (double &l : m.dv_edge) l /= r;
    return m;
}

// The spacing at each xEdge, on the unit sphere (sphere radius in km).
std::vector<double> spacing_at_edges(const um_spacing *h, const MpasArrays &m, double radius_km) {
    std::vector<double> lon, lat, km(static_cast<size_t>(m.n_edges));
    for (const V3 &p : m.x_edge) {
        lon.push_back(std::atan2(p.y, p.x) * 180 / M_PI);
        lat.push_back(std::asin(std::max(-1.0, std::min(1.0, p.z))) * 180 / M_PI);
    }
    if (um_spacing_evaluate(h, m.n_edges, lon.data(), lat.data(), km.data()) != UM_OK) die("spacing at edges");
    for (double &k : km) k /= radius_km;
    return km;
}

// --------------------------------------------------------------- the runs

struct MeshRun {
    std::string name, family;  // family: meshes whose errors give an order
    MpasArrays mesh;
    std::vector<uint8_t> near_gamma;  // cells next to a feature (coastline or river); empty without
    double seconds = 0;
};

std::string g_options;
int g_threads = 2;

void check(um_status s, um_context *ctx, const std::string &what) {
    if (s != UM_OK) die(what + ": " + um_context_last_error(ctx));
}

// Cells with an edge whose dual crosses a feature, and their neighbours.
std::vector<uint8_t> cells_next_to_features(MpasSource &s, const MpasArrays &m) {
    const std::vector<int32_t> kind = s.integer("edgeFeatureKind", m.n_edges);
    std::vector<uint8_t> on(static_cast<size_t>(m.n_cells), 0), near(on);
    for (int64_t e = 0; e < m.n_edges; ++e)
        if (kind[e] != 0) on[m.cells_on_edge[2 * e]] = on[m.cells_on_edge[2 * e + 1]] = 1;
    for (int64_t e = 0; e < m.n_edges; ++e) {
        const int32_t a = m.cells_on_edge[2 * e], b = m.cells_on_edge[2 * e + 1];
        if (on[a] || on[b]) near[a] = near[b] = 1;
    }
    return near;
}

MeshRun unimesh_run(const std::string &name, double km, bool features) {
    MeshRun run{name, features ? "coast-rivers" : "uniform", {}, {}, 0};
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) die("context");
    check(um_context_set_threads(ctx, g_threads), ctx, "threads");
    um_spacing *h = nullptr;
    check(um_spacing_create_constant(ctx, km, &h), ctx, "spacing");
    um_features *f = nullptr;
    if (features) {
        check(um_features_create(ctx, &f), ctx, "features");
        for (const char *file : {"coast_global_l.geojson", "rivers_global_l.geojson"})
            check(um_features_read_geojson(f, (std::string(UNIMESH_DATA_DIR) + "/" + file).c_str(), nullptr, 0),
                  ctx, file);
    }
    um_options *opts = nullptr;
    check(um_options_create(ctx, &opts), ctx, "options");
    check(um_options_set_string(opts, g_options.c_str()), ctx, "--options");
    double radius_m = 0;
    check(um_options_get_double(opts, UM_OPT_SPHERE_RADIUS, &radius_m), ctx, "radius");
    const auto t0 = Clock::now();
    um_mesh *m = nullptr;
    check(um_mesh_refine(ctx, h, f, opts, &m), ctx, "refine");
    check(um_mesh_optimise(m, opts), ctx, "optimise");
    run.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    LibrarySource source(m);
    run.mesh = read_mesh(source);
    run.mesh.h_edge = spacing_at_edges(h, run.mesh, radius_m / 1000);
    if (features) run.near_gamma = cells_next_to_features(source, run.mesh);
    um_mesh_destroy(m);
    um_options_destroy(opts);
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_context_destroy(ctx);
    return run;
}

MeshRun make_run(const std::string &spec) {
    const auto t0 = Clock::now();
    if (spec.rfind("ico-", 0) == 0) {
        MeshRun run{spec, "icosahedral", icosahedral_mesh(std::atoi(spec.c_str() + 4)), {}, 0};
        run.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        return run;
    }
    if (spec.rfind("uniform-", 0) == 0) return unimesh_run(spec, std::atof(spec.c_str() + 8), false);
    if (spec.rfind("coast-rivers-", 0) == 0) return unimesh_run(spec, std::atof(spec.c_str() + 13), true);
    if (spec.rfind("file:", 0) == 0) {
        FileSource source(spec.substr(5));
        MeshRun run{spec, spec, read_mesh(source), {}, 0};
        if (source.has("edgeFeatureKind")) run.near_gamma = cells_next_to_features(source, run.mesh);
        return run;
    }
    die("unknown case '" + spec + "' (ico-<level>, uniform-<km>, coast-rivers-<km>, file:<path>)");
}

// ------------------------------------------------------------- the tables

struct Column {
    const char *title;
    std::function<bench::RelativeError(const MpasArrays &, const bench::Selection &)> measure;
};

std::vector<Column> columns() {
    using namespace bench;
    static const ScalarField y32 = spherical_harmonic_32(), hill = gaussian_hill(),
                             solid = solid_body_stream(), rh4 = rossby_haurwitz_4_stream();
    return {
        {"grad psi", [](auto &m, auto &s) { return gradient_error(m, y32, s); }},
        {"grad hill", [](auto &m, auto &s) { return gradient_error(m, hill, s); }},
        {"div psi", [](auto &m, auto &s) { return divergence_error(m, divergent(y32), s); }},
        {"div hill", [](auto &m, auto &s) { return divergence_error(m, divergent(hill), s); }},
        {"curl psi", [](auto &m, auto &s) { return curl_error(m, rotational(y32), s); }},
        {"curl hill", [](auto &m, auto &s) { return curl_error(m, rotational(hill), s); }},
        {"curl SB", [](auto &m, auto &s) { return curl_error(m, rotational(solid), s); }},
        {"TRSK RH4", [](auto &m, auto &s) { return tangential_error(m, rotational(rh4), s); }},
        {"TRSK SB", [](auto &m, auto &s) { return tangential_error(m, rotational(solid), s); }},
        {"KE RH4", [](auto &m, auto &s) { return kinetic_energy_error(m, rotational(rh4), s); }},
        {"KE SB", [](auto &m, auto &s) { return kinetic_energy_error(m, rotational(solid), s); }},
    };
}

struct Row {
    std::string name, family;
    int64_t cells;
    std::vector<bench::RelativeError> errors;
};

void print_errors(const std::vector<Row> &rows, bool linf) {
    const std::vector<Column> cols = columns();
    std::printf("\n## relative %s errors\n%-28s %9s", linf ? "Linf" : "L2", "mesh", "cells");
    for (const Column &c : cols) std::printf(" %9s", c.title);
    std::printf("\n");
    for (const Row &r : rows) {
        std::printf("%-28s %9lld", r.name.c_str(), static_cast<long long>(r.cells));
        for (const auto &e : r.errors) std::printf(" %9.2e", linf ? e.linf : e.l2);
        std::printf("\n");
    }
}

// Observed orders -2 ln(E2/E1) / ln(N2/N1) between consecutive meshes of a
// family (rows of the whole meshes only), in L2.
void print_orders(const std::vector<Row> &rows) {
    const std::vector<Column> cols = columns();
    std::printf("\n## observed orders (L2) between consecutive meshes of a family\n%-28s", "meshes");
    for (const Column &c : cols) std::printf(" %9s", c.title);
    std::printf("\n");
    std::map<std::string, std::vector<const Row *>> families;
    for (const Row &r : rows)
        if (!r.family.empty()) families[r.family].push_back(&r);
    for (auto &[family, members] : families) {
        std::sort(members.begin(), members.end(), [](const Row *a, const Row *b) { return a->cells < b->cells; });
        for (size_t i = 1; i < members.size(); ++i) {
            const Row &a = *members[i - 1], &b = *members[i];
            std::printf("%-28s", (a.name + " -> " + b.name.substr(b.name.rfind('-') + 1)).c_str());
            for (size_t k = 0; k < cols.size(); ++k)
                std::printf(" %9.2f", -2 * std::log(b.errors[k].l2 / a.errors[k].l2) /
                                          std::log(double(b.cells) / double(a.cells)));
            std::printf("\n");
        }
    }
}

void print_diagnostics(const std::vector<MeshRun> &runs) {
    std::printf("\n## mesh diagnostics (rms / max; dcEdge/h: min max mean std; sides: cells with <5 5 7 >7)\n");
    std::printf("%-22s %9s %17s %17s %17s %27s %15s %23s %7s\n", "mesh", "cells", "centroid offset",
                "dual-edge offset", "primal-edge off.", "dcEdge/h", "Q^T min mean", "sides <5/5/7/>7", "seconds");
    for (const MeshRun &r : runs) {
        const bench::Diagnostics d = bench::diagnose(r.mesh);
        std::printf("%-22s %9lld %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f", r.name.c_str(),
                    static_cast<long long>(r.mesh.n_cells), d.centroid_offset.rms, d.centroid_offset.max,
                    d.dual_edge_offset.rms, d.dual_edge_offset.max, d.primal_edge_offset.rms,
                    d.primal_edge_offset.max);
        if (d.spacing_ratio.count > 0)
            std::printf(" %6.3f %6.3f %6.4f %6.4f", d.spacing_ratio.min, d.spacing_ratio.max, d.spacing_ratio.mean,
                        d.spacing_ratio.std);
        else
            std::printf(" %27s", "-");
        std::printf(" %7.4f %7.4f %5lld/%5lld/%5lld/%5lld %7.2f\n", d.area_length.min, d.area_length.mean,
                    static_cast<long long>(d.sides[0]), static_cast<long long>(d.sides[1]),
                    static_cast<long long>(d.sides[2]), static_cast<long long>(d.sides[3]), r.seconds);
    }
}

// The ico-6 figures of the operator definitions' reference table.
bool validate(const std::vector<Row> &rows, const std::vector<MeshRun> &runs) {
    const Row *row = nullptr;
    const MeshRun *run = nullptr;
    for (size_t i = 0; i < rows.size(); ++i)
        if (rows[i].name == "ico-6") row = &rows[i];
    for (const MeshRun &r : runs)
        if (r.name == "ico-6") run = &r;
    if (!row || !run) {
        std::printf("# validate: no ico-6 case\n");
        return false;
    }
    const bench::Diagnostics d = bench::diagnose(run->mesh);
    const std::vector<Column> cols = columns();
    auto l2_of = [&](const std::string &title) {
        for (size_t k = 0; k < cols.size(); ++k)
            if (title == cols[k].title) return row->errors[k].l2;
        die("no column " + title);
    };
    const std::vector<std::pair<std::string, std::pair<double, double>>> expected = {
        {"div psi", {l2_of("div psi"), 1.4e-3}},   {"curl psi", {l2_of("curl psi"), 3.2e-3}},
        {"TRSK RH4", {l2_of("TRSK RH4"), 1.6e-2}}, {"KE RH4", {l2_of("KE RH4"), 1.9e-3}},
        {"centroid offset rms", {d.centroid_offset.rms, 0.0092}},
        {"dual-edge offset rms", {d.dual_edge_offset.rms, 0.013}}};
    bool ok = true;
    for (const auto &[what, got_want] : expected) {
        const bool close = std::fabs(got_want.first / got_want.second - 1) <= 0.12;
        std::printf("# validate ico-6 %-22s %.3e, reference %.1e: %s\n", what.c_str(), got_want.first,
                    got_want.second, close ? "ok" : "OFF");
        ok = ok && close;
    }
    return ok;
}

}  // namespace

int main(int argc, char **argv) {
    std::string cases = "ico-5,ico-6,ico-7,uniform-240,uniform-120,uniform-60,coast-rivers-60";
    bool check_reference = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--cases" && i + 1 < argc) cases = argv[++i];
        else if (a == "--threads" && i + 1 < argc) g_threads = std::atoi(argv[++i]);
        else if (a == "--options" && i + 1 < argc) g_options = argv[++i];
        else if (a == "--validate") check_reference = true;
        else die("unknown argument '" + a + "' (see the comment at the top of bench_operators.cpp)");
    }
    std::vector<MeshRun> runs;
    for (size_t at = 0; at <= cases.size();) {
        const size_t comma = std::min(cases.find(',', at), cases.size());
        if (comma > at) {
            runs.push_back(make_run(cases.substr(at, comma - at)));
            std::fprintf(stderr, "bench_operators: %s ready (%lld cells, %.1f s)\n", runs.back().name.c_str(),
                         static_cast<long long>(runs.back().mesh.n_cells), runs.back().seconds);
        }
        at = comma + 1;
    }
    std::printf("# bench_operators: %zu meshes, %d threads, options \"%s\"\n", runs.size(), g_threads,
                g_options.c_str());
    const std::vector<Column> cols = columns();
    std::vector<Row> rows;
    for (const MeshRun &r : runs) {
        const bench::Selection all;
        Row row{r.name, r.family, r.mesh.n_cells, {}};
        for (const Column &c : cols) row.errors.push_back(c.measure(r.mesh, all));
        rows.push_back(row);
        if (r.near_gamma.empty()) continue;
        std::vector<uint8_t> away(r.near_gamma.size());
        for (size_t i = 0; i < away.size(); ++i) away[i] = !r.near_gamma[i];
        for (const auto &[label, cells] : {std::pair<const char *, const std::vector<uint8_t> *>{" next to G", &r.near_gamma},
                                           {" away from G", &away}}) {
            const bench::Selection part = bench::Selection::of_cells(r.mesh, *cells);
            Row sub{r.name + label, "", 0, {}};
            for (uint8_t c : *cells) sub.cells += c;
            for (const Column &c : cols) sub.errors.push_back(c.measure(r.mesh, part));
            rows.push_back(sub);
        }
    }
    print_errors(rows, false);
    print_errors(rows, true);
    print_orders(rows);
    print_diagnostics(runs);
    if (check_reference && !validate(rows, runs)) return 1;
    return 0;
}
