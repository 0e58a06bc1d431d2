// libFuzzer target: short sequences of C API calls chosen by the input, on
// small inputs it also chooses (points, weights, spacings, options, buffer
// sizes, handles in any state, destroyed ones included). The C ABI promises
// a status for every call: no crash, no exception, no sanitizer report.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "unimesh.h"

namespace {

// Reads the input as a stream of small values.
struct Bytes {
    const uint8_t *p;
    size_t n;
    uint8_t byte() {
        if (n == 0) return 0;
        --n;
        return *p++;
    }
    double real(double lo, double hi) { return lo + (hi - lo) * byte() / 255.0; }
    // Sometimes a hostile value: NaN, Inf, negative, huge.
    double value(double lo, double hi) {
        switch (byte() % 16) {
            case 0: return NAN;
            case 1: return INFINITY;
            case 2: return -hi;
            case 3: return 1e300;
            default: return real(lo, hi);
        }
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Bytes in{data, size};
    um_context *ctx = nullptr;
    if (um_context_create(&ctx) != UM_OK) return 0;
    um_context_set_threads(ctx, 1 + in.byte() % 2);
    um_spacing *h = nullptr;
    um_features *f = nullptr;
    um_options *o = nullptr;
    um_mesh *m = nullptr;
    um_triangulation *t = nullptr;
    std::vector<double> buffer;
    std::vector<int32_t> ints;
    for (int step = 0; step < 12 && in.n > 0; ++step) {
        switch (in.byte() % 12) {
            case 0:
                um_spacing_destroy(h), h = nullptr;
                um_spacing_create_constant(ctx, in.value(800, 3000), &h);
                break;
            case 1: {
                if (!f) um_features_create(ctx, &f);
                const int n = 2 + in.byte() % 8;
                std::vector<double> lon(n), lat(n);
                for (int i = 0; i < n; ++i) lon[i] = in.value(-180, 180), lat[i] = in.value(-90, 90);
                int64_t offsets[2] = {0, n};
                int32_t closed = in.byte() % 2, kind = 1 + in.byte() % 6;
                um_features_add(f, n, lon.data(), lat.data(), 1, offsets, &closed, &kind, nullptr);
                break;
            }
            case 2:
                um_options_destroy(o), o = nullptr;
                um_options_create(ctx, &o);
                um_options_set_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, in.byte() % 4);
                um_options_set_double(o, UM_OPT_REFINE_RHO, in.value(1, 3));
                break;
            case 3:
                if (h && !m) um_mesh_refine(ctx, h, f, o, &m);
                break;
            case 4:
                um_mesh_optimise(m, o);
                break;
            case 5: {
                int64_t nc = 0;
                um_mesh_mpas_dimensions(m, &nc, nullptr, nullptr, nullptr);
                buffer.assign(size_t(in.byte()), 0.0);
                um_mesh_copy_mpas_real(m, in.byte() % 2 ? "areaCell" : "noSuch", buffer.data(),
                                       int64_t(buffer.size()));
                ints.assign(size_t(in.byte()) * 2, 0);
                um_mesh_copy_mpas_int(m, "cellsOnEdge", in.byte() % 3, ints.data(), int64_t(ints.size()));
                break;
            }
            case 6: {
                char text[8];
                int64_t needed = 0;
                um_mesh_quality_json(m, text, in.byte() % 9, &needed);
                um_context_last_error(ctx);
                break;
            }
            case 7: {
                const int n = in.byte() % 24;
                std::vector<double> lon(n), lat(n), w(n);
                for (int i = 0; i < n; ++i) lon[i] = in.value(-180, 180), lat[i] = in.value(-90, 90), w[i] = in.value(-0.01, 0.01);
                um_triangulation_destroy(t), t = nullptr;
                um_triangulation_create(ctx, n, lon.data(), lat.data(), in.byte() % 2 ? w.data() : nullptr, &t);
                break;
            }
            case 8:
                ints.assign(size_t(in.byte()) * 3, 0);
                um_triangulation_copy_triangles(t, in.byte() % 2, ints.data(), int64_t(ints.size()));
                break;
            case 9:  // destroy something and keep using the dangling handle: must be refused
                if (in.byte() % 2) {
                    um_mesh_destroy(m);
                    um_mesh_counts(m, nullptr, nullptr, nullptr, nullptr);
                    m = nullptr;
                } else {
                    um_spacing_destroy(h);
                    h = nullptr;
                }
                break;
            case 10:
                um_context_clear_error(ctx);
                break;
            default: {
                std::string s;
                for (int i = 0; i < 6; ++i) s += char(in.byte());
                um_options_set_string(o, s.c_str());
                break;
            }
        }
    }
    um_mesh_destroy(m);
    um_triangulation_destroy(t);
    um_options_destroy(o);
    um_features_destroy(f);
    um_spacing_destroy(h);
    um_context_destroy(ctx);
    return 0;
}
