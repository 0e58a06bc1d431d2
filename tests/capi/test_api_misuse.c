/* CMocka suite: the API used wrongly must return codes, never crash. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "unimesh.h"

static void null_handles(void **state) {
    (void)state;
    int32_t n = 0;
    int64_t cap = 0;
    assert_int_equal(um_context_create(NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_threads(NULL, 1), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_get_threads(NULL, &n), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_memory_cap(NULL, 1), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_get_memory_cap(NULL, &cap), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_progress(NULL, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_log(NULL, NULL, NULL, 0), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_set_error_mode(NULL, 0, NULL, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_clear_error(NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_context_copy_last_error(NULL, NULL, 0, NULL), UM_ERR_NULL_ARGUMENT);
    assert_string_equal(um_context_last_error(NULL), "");
    assert_int_equal(um_context_last_status(NULL), UM_OK);
    um_context_destroy(NULL);
    um_options *o = NULL;
    double v = 0;
    int64_t i = 0;
    assert_int_equal(um_options_create(NULL, &o), UM_ERR_NULL_ARGUMENT);
    assert_null(o);
    assert_int_equal(um_options_set_double(NULL, UM_OPT_REFINE_ALPHA, 1.0), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_set_int(NULL, UM_OPT_OPTIM_WEIGHTS, 1), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_get_double(NULL, UM_OPT_REFINE_ALPHA, &v), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_get_int(NULL, UM_OPT_OPTIM_WEIGHTS, &i), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_set_string(NULL, "a=1"), UM_ERR_NULL_ARGUMENT);
    um_options_destroy(NULL);
    assert_int_equal(um_option_key(NULL, NULL), UM_ERR_NULL_ARGUMENT);
}

static void null_out_arguments(void **state) {
    (void)state;
    um_context *ctx = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    um_options *o = NULL;
    assert_int_equal(um_options_create(ctx, NULL), UM_ERR_NULL_ARGUMENT);
    assert_non_null(strstr(um_context_last_error(ctx), "out"));
    assert_int_equal(um_context_get_threads(ctx, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_ALPHA, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_options_set_string(o, NULL), UM_ERR_NULL_ARGUMENT);
    um_options_destroy(o);
    um_context_destroy(ctx);
}

static void foreign_handles(void **state) {
    (void)state;
    um_context *ctx = NULL;
    um_options *o = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    /* an options handle where a context is expected, and the other way round */
    assert_int_equal(um_context_set_threads((um_context *)o, 1), UM_ERR_INVALID_HANDLE);
    assert_int_equal(um_options_set_double((um_options *)ctx, UM_OPT_REFINE_ALPHA, 1.0),
                     UM_ERR_INVALID_HANDLE);
    /* a pointer to something that is not a handle at all */
    double not_a_handle[8] = {0};
    assert_int_equal(um_context_set_threads((um_context *)not_a_handle, 1), UM_ERR_INVALID_HANDLE);
    assert_string_equal(um_context_last_error((um_context *)not_a_handle), "");
    um_context_destroy((um_context *)not_a_handle); /* ignored */
    um_options_destroy((um_options *)ctx);          /* wrong kind: ignored */
    int32_t n = 0;
    assert_int_equal(um_context_get_threads(ctx, &n), UM_OK); /* ctx still alive */
    um_options_destroy(o);
    um_context_destroy(ctx);
}

static void double_destroy_and_use_after_destroy(void **state) {
    (void)state;
    um_context *ctx = NULL;
    um_options *o = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    um_options_destroy(o);
    um_options_destroy(o);
    assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_ALPHA, 1.0), UM_ERR_INVALID_HANDLE);
    um_context_destroy(ctx);
    um_context_destroy(ctx);
    assert_int_equal(um_context_set_threads(ctx, 1), UM_ERR_INVALID_HANDLE);
    assert_string_equal(um_context_last_error(ctx), "");
    um_options *o2 = NULL;
    assert_int_equal(um_options_create(ctx, &o2), UM_ERR_INVALID_HANDLE);
    assert_null(o2);
}

static void out_of_range_and_nan_option_values(void **state) {
    (void)state;
    um_context *ctx = NULL;
    um_options *o = NULL;
    assert_int_equal(um_context_create(&ctx), UM_OK);
    assert_int_equal(um_options_create(ctx, &o), UM_OK);
    const double bad[] = {NAN, -NAN, INFINITY, -INFINITY, -1e308, 1e308, 0.0};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(um_options_set_double(o, UM_OPT_REFINE_RHO, bad[i]),
                         UM_ERR_INVALID_ARGUMENT);
    }
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, -1),
                     UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_int(o, UM_OPT_OPTIM_OUTER_ITERATIONS, INT64_MAX),
                     UM_ERR_INVALID_ARGUMENT);
    assert_int_equal(um_options_set_int(o, -5, 1), UM_ERR_UNKNOWN_OPTION);
    assert_int_equal(um_options_set_string(o, "=;=;"), UM_ERR_UNKNOWN_OPTION);
    assert_int_equal(um_options_set_string(o, "refine_rho=1e999"), UM_ERR_INVALID_ARGUMENT);
    double rho = 0;
    assert_int_equal(um_options_get_double(o, UM_OPT_REFINE_RHO, &rho), UM_OK);
    assert_true(rho == 1.05);
    um_options_destroy(o);
    um_context_destroy(ctx);
}

static void tiny_message_buffers(void **state) {
    (void)state;
    char buf[1];
    int64_t needed = 0;
    assert_int_equal(um_option_name(UM_OPT_REFINE_ALPHA, NULL, 0, &needed), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(needed, (int64_t)strlen("refine_alpha") + 1);
    assert_int_equal(um_option_name(UM_OPT_REFINE_ALPHA, buf, 1, NULL), UM_ERR_BUFFER_TOO_SMALL);
    assert_int_equal(buf[0], '\0');
    assert_int_equal(um_option_name(UM_OPT_REFINE_ALPHA, NULL, 8, NULL), UM_ERR_NULL_ARGUMENT);
    assert_int_equal(um_option_name(UM_OPT_REFINE_ALPHA, buf, -1, NULL), UM_ERR_INVALID_ARGUMENT);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(null_handles),
        cmocka_unit_test(null_out_arguments),
        cmocka_unit_test(foreign_handles),
        cmocka_unit_test(double_destroy_and_use_after_destroy),
        cmocka_unit_test(out_of_range_and_nan_option_values),
        cmocka_unit_test(tiny_message_buffers),
    };
    return cmocka_run_group_tests_name("api_misuse", tests, NULL, NULL);
}
