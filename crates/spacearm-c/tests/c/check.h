/* The checks of the C tests (test_c_api.c, test_c_controllers.c): CHECK(cond, fmt, ...) counts
 * and reports a failed condition; OK(call) checks that a spacearm call returned
 * SPACEARM_STATUS_OK, with the status name and the last error's message. Each test program
 * includes it once and returns `failures != 0`. */
#ifndef SPACEARM_TEST_CHECK_H
#define SPACEARM_TEST_CHECK_H

#include <stdio.h>

#include "spacearm.h"

static int failures = 0;
#define CHECK(cond, ...)                                                   \
    do {                                                                   \
        if (!(cond)) {                                                     \
            failures++;                                                    \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                  \
            fprintf(stderr, "\n");                                         \
        }                                                                  \
    } while (0)
#define OK(call)                                                           \
    do {                                                                   \
        SpacearmStatus s_ = (call);                                        \
        CHECK(s_ == SPACEARM_STATUS_OK, "%s -> %s: %s", #call, spacearm_status_name(s_), spacearm_last_error()); \
    } while (0)

#endif
