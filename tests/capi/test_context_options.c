/* CMocka suite: version, status codes, the context and the options object. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "context_fixture.h"
#include "unimesh.h"

static void version_macros_agree_with_runtime(void **state) {
    (void)state;
    int32_t major = -1, minor = -1, patch = -1;
    um_version(&major, &minor, &patch);
    assert_int_equal(major, UM_VERSION_MAJOR);
    assert_int_equal(minor, UM_VERSION_MINOR);
    assert_int_equal(patch, UM_VERSION_PATCH);
    assert_int_equal(um_version_number(), UM_VERSION_NUMBER);
    assert_string_equal(um_version_string(), UM_VERSION_STRING);
    um_version(NULL, NULL, NULL); /* NULLs allowed */
}

static void status_strings_and_bands(void **state) {
    (void)state;
    assert_string_equal(um_status_string(UM_OK), "success");
    assert_string_equal(um_status_string(12345), "unknown status");
    assert_int_equal(um_status_class(UM_OK), 0);
    assert_int_equal(um_status_class(UM_ERR_INVALID_HANDLE), 100);
    assert_int_equal(um_status_class(UM_ERR_DUPLICATE_POINTS), 200);
    assert_int_equal(um_status_class(UM_ERR_NUMERICAL), 300);
    assert_int_equal(um_status_class(UM_ERR_MEMORY_CAP), 400);
    assert_int_equal(um_status_class(UM_ERR_FILE_FORMAT), 500);
    assert_int_equal(um_status_class(UM_CANCELLED), 600);
    assert_int_equal(um_status_class(UM_ERR_INTERNAL), 900);
    assert_int_equal(um_status_class(-3), 900);
    /* Pinned values: changing one breaks every compiled caller. */
    assert_int_equal(UM_ERR_NULL_ARGUMENT, 101);
    assert_int_equal(UM_ERR_INVALID_ARGUMENT, 103);
    assert_int_equal(UM_ERR_MEMORY_CAP, 401);
    for (um_status s = 0; s < 1000; ++s) assert_non_null(um_status_string(s));
}

static void threads_resolve_and_reject(void **state) {
    um_context *ctx = *state;
    int32_t n = 0;
    assert_int_equal(um_context_set_threads(ctx, 3), UM_OK);
    assert_int_equal(um_context_get_threads(ctx, &n), UM_OK);
    assert_int_equal(n, 3);
    assert_int_equal(um_context_set_threads(ctx, 0), UM_OK);
    assert_int_equal(um_context_get_threads(ctx, &n), UM_OK);
    assert_true(n >= 1);
    int32_t before = n;
    assert_int_equal(um_context_set_threads(ctx, -2), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "n_threads = -2"));
    assert_int_equal(um_context_get_threads(ctx, &n), UM_OK);
    assert_int_equal(n, before); /* unchanged by the failed call */
}

static void first_error_is_kept_until_cleared(void **state) {
    um_context *ctx = *state;
    assert_string_equal(um_context_last_error(ctx), "");
    assert_int_equal(um_context_last_status(ctx), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, 5000), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_context_set_memory_cap(ctx, -1), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "5000"));
    assert_int_equal(um_context_last_status(ctx), UM_ERR_INVALID_ARGUMENT);
    /* reading does not clear */
    assert_non_null(strstr(um_context_last_error(ctx), "5000"));
    assert_int_equal(um_context_clear_error(ctx), UM_OK);
    assert_string_equal(um_context_last_error(ctx), "");
    assert_int_equal(um_context_set_memory_cap(ctx, -1), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "bytes = -1"));
}

static void message_copied_into_small_buffers(void **state) {
    um_context *ctx = *state;
    assert_int_equal(um_context_set_threads(ctx, -7), UM_ERR_INVALID_ARGUMENT);
    const char *full = um_context_last_error(ctx);
    int64_t needed = 0;
    assert_int_equal(um_context_copy_last_error(ctx, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(needed, (int64_t)strlen(full) + 1);
    char one[1] = {'x'};
    assert_int_equal(um_context_copy_last_error(ctx, one, 1, &needed), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(one[0], '\0');
    char five[5];
    assert_int_equal(um_context_copy_last_error(ctx, five, 5, NULL), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(strlen(five), 4);
    assert_memory_equal(five, full, 4);
    char big[512];
    assert_int_equal(um_context_copy_last_error(ctx, big, sizeof big, &needed), UM_OK);
    assert_string_equal(big, full);
    assert_int_equal(um_context_copy_last_error(ctx, NULL, 4, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_copy_last_error(ctx, big, -1, NULL), UM_ERR_INVALID_ARGUMENT);
}

typedef struct {
    int calls;
    um_status status;
    char message[256];
} abort_record;

static void record_abort(void *user, um_status status, const char *message) {
    abort_record *r = user;
    r->calls++;
    r->status = status;
    strncpy(r->message, message, sizeof r->message - 1);
}

static void abort_mode_calls_the_hook(void **state) {
    um_context *ctx = *state;
    abort_record rec = {0, 0, {0}};
    assert_int_equal(um_context_set_error_mode(ctx, UM_ERROR_MODE_ABORT, NULL, NULL),
                     UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_error_mode(ctx, 7, record_abort, &rec),
                     UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_context_clear_error(ctx), UM_OK);
    assert_int_equal(um_context_set_error_mode(ctx, UM_ERROR_MODE_ABORT, record_abort, &rec),
                     UM_OK);
    assert_int_equal(rec.calls, 0);
    assert_int_equal(um_context_set_threads(ctx, -1), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(rec.calls, 1);
    assert_int_equal(rec.status, UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(rec.message, "n_threads = -1"));
    assert_int_equal(um_context_set_error_mode(ctx, UM_ERROR_MODE_RETURN, NULL, NULL), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, -1), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(rec.calls, 1);
}

typedef struct {
    int calls;
    int32_t level;
} log_record;

static void record_log(void *user, int32_t level, const char *message) {
    log_record *r = user;
    (void)message;
    r->calls++;
    r->level = level;
}

static void errors_reach_the_log_callback(void **state) {
    um_context *ctx = *state;
    log_record rec = {0, 0};
    assert_int_equal(um_context_set_log(ctx, record_log, &rec, UM_LOG_INFO), UM_OK);
    assert_int_equal(um_context_set_threads(ctx, -1), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(rec.calls, 1);
    assert_int_equal(rec.level, UM_LOG_ERROR);
    assert_int_equal(um_context_set_log(ctx, NULL, NULL, UM_LOG_INFO), UM_OK);
}

static void memory_cap_round_trip(void **state) {
    um_context *ctx = *state;
    int64_t cap = -1;
    assert_int_equal(um_context_get_memory_cap(ctx, &cap), UM_OK);
    assert_int_equal(cap, 0);
    assert_int_equal(um_context_set_memory_cap(ctx, 1 << 20), UM_OK);
    assert_int_equal(um_context_get_memory_cap(ctx, &cap), UM_OK);
    assert_int_equal(cap, 1 << 20);
}

static void options_typed_setters_and_bounds(void **state) {
    um_context *ctx = *state;
    um_options *o = NULL;
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    double v = 0, lo = 0, hi = 0, def = 0;
    int32_t type = 0;
    assert_int_equal(um_option_info(UM_OPT_REFINE_ALPHA, &type, &lo, &hi, &def), UM_OK);
    assert_int_equal(type, UM_OPTION_TYPE_REAL);
    assert_true(lo <= def && def <= hi);
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_ALPHA, &v), UM_OK);
    assert_true(fabs(v - 4.0 / 3.0) < 1e-15);
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, 1.25), UM_OK);
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_ALPHA, &v), UM_OK);
    assert_true(v == 1.25);

    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, hi * 2), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "refine_alpha"));
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, NAN), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, INFINITY), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_ALPHA, &v), UM_OK);
    assert_true(v == 1.25); /* unchanged */

    int64_t n = 0;
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, &n), UM_OK);
    assert_int_equal(n, 20);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, 4), UM_OK);
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, &n), UM_OK);
    assert_int_equal(n, 4);
    assert_int_equal(um_options_set_double(o, UM_OPT_OPTIM_OUTER_ITERATIONS, 3.0), UM_ERR_OPTION_TYPE);
    assert_int_equal(um_options_set_int(o, UM_OPT_REFINE_ALPHA, 1), UM_ERR_OPTION_TYPE);
    assert_int_equal(um_options_set_int(o, 99999, 1), UM_ERR_UNKNOWN_OPTION);
    assert_int_equal(um_option_info(99999, NULL, NULL, NULL, NULL), UM_ERR_UNKNOWN_OPTION);
    um_options_destroy(o);
}

static void options_from_string_all_or_nothing(void **state) {
    um_context *ctx = *state;
    um_options *o = NULL;
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    assert_int_equal(um_options_set_string(o, " refine_rho = 1.2 ; optim_inner_iterations=3;;"),
                     UM_OK);
    double v = 0;
    int64_t n = 0;
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_RHO, &v), UM_OK);
    assert_true(v == 1.2);
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_INNER_ITERATIONS, &n), UM_OK);
    assert_int_equal(n, 3);
    /* the second item is bad: the first must not be applied */
    assert_int_equal(um_options_set_string(o, "refine_rho=1.5;optim_inner_iterations=2.5"),
                     UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "optim_inner_iterations"));
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_RHO, &v), UM_OK);
    assert_true(v == 1.2);
    assert_int_equal(um_options_set_string(o, "no_such_option=1"), UM_ERR_UNKNOWN_OPTION);
    assert_int_equal(um_options_set_string(o, "refine_rho"), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_string(o, "refine_rho=nan"), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_string(o, "refine_rho=1.1x"), UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_string(o, ""), UM_OK);
    um_options_destroy(o);
}

static void option_names_round_trip(void **state) {
    (void)state;
    const um_option keys[] = {UM_OPT_SPHERE_RADIUS, UM_OPT_REFINE_ALPHA, UM_OPT_REFINE_BETA,
                              UM_OPT_REFINE_RHO, UM_OPT_REFINE_LATTICE, UM_OPT_OPTIM_OUTER_ITERATIONS,
                              UM_OPT_OPTIM_SPLIT_RATIO, UM_OPT_OPTIM_CORNER_VERTICES,
                              UM_OPT_OPTIM_CENTROIDAL_SWEEPS, UM_OPT_OPTIM_RESEED_ROUNDS,
                              UM_OPT_OCEAN_FLOOR};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i) {
        char name[64];
        int64_t needed = 0;
        assert_int_equal(um_option_name(keys[i], name, sizeof name, &needed), UM_OK);
        um_option back = 0;
        assert_int_equal(um_option_key(name, &back), UM_OK);
        assert_int_equal(back, keys[i]);
    }
    um_option k = 0;
    assert_int_equal(um_option_key("nonsense", &k), UM_ERR_UNKNOWN_OPTION);
    /* optim_corner_vertices: 0, 1 or 2 (only where the new cells stay clear of the features) */
    um_context *ctx = NULL;
    um_options *o = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_CORNER_VERTICES, 2), UM_OK);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_CORNER_VERTICES, 3), UM_ERR_INVALID_ARGUMENT);
    int64_t value = 0;
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_CORNER_VERTICES, &value), UM_OK);
    assert_int_equal(value, 2);
    /* optim_centroidal_sweeps: 8 by default, 0 turns the centroidal pass off */
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_CENTROIDAL_SWEEPS, &value), UM_OK);
    assert_int_equal(value, 8);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_CENTROIDAL_SWEEPS, 0), UM_OK);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_CENTROIDAL_SWEEPS, -1), UM_ERR_INVALID_ARGUMENT);
    /* optim_reseed_rounds: 7 by default, 0 turns the re-seeding of defects off */
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_RESEED_ROUNDS, &value), UM_OK);
    assert_int_equal(value, 7);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_RESEED_ROUNDS, 0), UM_OK);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_RESEED_ROUNDS, -1), UM_ERR_INVALID_ARGUMENT);
    /* ocean_floor: 0.7 by default, 0 turns it off, at most 0.9 */
    double floor = 1;
    assert_int_equal(um_options_get_double(o, UM_OPT_OCEAN_FLOOR, &floor), UM_OK);
    assert_true(floor == 0.7);
    assert_int_equal(um_options_set_double(o, UM_OPT_OCEAN_FLOOR, 0.0), UM_OK);
    um_context_clear_error(ctx);
    assert_int_equal(um_options_set_double(o, UM_OPT_OCEAN_FLOOR, 0.95), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "ocean_floor"));
    /* Worker placement: asked for with 1, off again with 0, nothing else. */
    um_context_clear_error(ctx);
    assert_int_equal(um_context_set_worker_placement(ctx, 1), UM_OK);
    assert_int_equal(um_context_set_worker_placement(ctx, 0), UM_OK);
    assert_int_equal(um_context_set_worker_placement(ctx, 2), UM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "on = 2"));
    um_context_clear_error(ctx);
    assert_int_equal(um_context_set_worker_placement(NULL, 1), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_set_string(o, "optim_reseed_rounds=3"), UM_OK);
    assert_int_equal(um_options_get_int(o, UM_OPT_OPTIM_RESEED_ROUNDS, &value), UM_OK);
    assert_int_equal(value, 3);
    um_options_destroy(o);
    um_context_destroy(ctx);
}

static void context_outlives_nothing_objects_outlive_context(void **state) {
    (void)state;
    um_context *ctx = NULL;
    um_options *o = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    um_context_destroy(ctx);
    /* the options object stays usable after its context is gone */
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_BETA, 0.1), UM_OK);
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_BETA, -1.0), UM_ERR_INVALID_ARGUMENT);
    um_options_destroy(o);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(version_macros_agree_with_runtime),
        cmocka_unit_test(status_strings_and_bands),
        cmocka_unit_test_setup_teardown(threads_resolve_and_reject, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(first_error_is_kept_until_cleared, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(message_copied_into_small_buffers, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(abort_mode_calls_the_hook, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(errors_reach_the_log_callback, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(memory_cap_round_trip, setup_context, teardown_context),
        cmocka_unit_test_setup_teardown(options_typed_setters_and_bounds, setup_context,
                                        teardown_context),
        cmocka_unit_test_setup_teardown(options_from_string_all_or_nothing, setup_context,
                                        teardown_context),
        cmocka_unit_test(option_names_round_trip),
        cmocka_unit_test(context_outlives_nothing_objects_outlive_context),
    };
    return cmocka_run_group_tests_name("context_options", tests, NULL, NULL);
}
