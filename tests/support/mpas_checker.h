/* For the C ABI suites that write MPAS meshes: the shared MPAS checker
 * (../shared/tools/mpas_check.py) run on a file, and a dimension read back
 * with netCDF-C. UNIMESH_SHARED_DIR is set by tests/CMakeLists.txt. */
#ifndef UNIMESH_TESTS_MPAS_CHECKER_H
#define UNIMESH_TESTS_MPAS_CHECKER_H

#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <netcdf.h>

static const char *const kPython = "/usr/bin/python3";
static const char *const kChecker = UNIMESH_SHARED_DIR "/tools/mpas_check.py";

/* Runs the shared checker on path and echoes its lines; it must exit 0.
 * Without ../shared beside the project there is no checker (the project
 * builds and tests without it): skipped, and said so. Where the checker is
 * there, a Python without numpy and netCDF4 (which tools/setup.sh installs)
 * is a failure, not a silent pass. */
static void run_checker(const char *path) {
    if (access(kChecker, R_OK) != 0) {
        printf("%s not found: checker skipped for %s\n", kChecker, path);
        return;
    }
    if (access(kPython, X_OK) != 0 || system("/usr/bin/python3 -c 'import numpy, netCDF4' >/dev/null 2>&1") != 0)
        fail_msg("%s is there but %s cannot import numpy and netCDF4 to run it", kChecker, kPython);
    char command[4096];
    snprintf(command, sizeof command, "%s %s %s 2>&1", kPython, kChecker, path);
    FILE *out = popen(command, "r");
    assert_non_null(out);
    char line[1024];
    while (fgets(line, sizeof line, out)) printf("  %s", line);
    int status = pclose(out);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}

/* The length of dimension name of the open file nc (it must be there). */
static size_t dim_length(int nc, const char *name) {
    int id = -1;
    size_t n = 0;
    assert_int_equal(nc_inq_dimid(nc, name, &id), NC_NOERR);
    assert_int_equal(nc_inq_dimlen(nc, id, &n), NC_NOERR);
    return n;
}

#endif
