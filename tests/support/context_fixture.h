/* The CMocka group fixture of the C ABI suites: one context per suite,
 * handed to each test as *state. */
#ifndef UNIMESH_TESTS_CONTEXT_FIXTURE_H
#define UNIMESH_TESTS_CONTEXT_FIXTURE_H

#include "unimesh.h"

static int setup_context(void **state) {
    um_context *ctx = NULL;
    if (um_context_create(&ctx) != UM_OK) return -1;
    *state = ctx;
    return 0;
}

static int teardown_context(void **state) {
    um_context_destroy((um_context *)*state);
    return 0;
}

#endif
