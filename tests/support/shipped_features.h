/* The features the project ships (data/): the global coastlines and, when
 * asked, the rivers, read into a new features object of ctx. Include after
 * cmocka.h, in a suite compiled with UNIMESH_DATA_DIR. */
#ifndef UNIMESH_TESTS_SHIPPED_FEATURES_H
#define UNIMESH_TESTS_SHIPPED_FEATURES_H

#include "unimesh.h"

static inline um_features *shipped_features(um_context *ctx, int with_rivers) {
    um_features *f = NULL;
    assert_int_equal(um_features_create(ctx, &f), UM_OK);
    assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/coast_global_l.geojson", NULL, 0), UM_OK);
    if (with_rivers)
        assert_int_equal(um_features_read_geojson(f, UNIMESH_DATA_DIR "/rivers_global_l.geojson", NULL, 0), UM_OK);
    return f;
}

#endif
