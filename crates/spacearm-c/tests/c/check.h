/* The checks of the C tests (test_c_api.c, test_c_controllers.c): CHECK(cond, fmt, ...) counts
 * and reports a failed condition with a message; OK(call) checks that a spacearm call answers
 * SPACEARM_STATUS_OK, else reports its status name and the library's last error;
 * FAILED() reports the count of failed checks at the end of a test's main (true if any failed:
 * main returns 1). Include after <stdio.h> and "spacearm.h". */
#ifndef SPACEARM_TEST_CHECK_H
#define SPACEARM_TEST_CHECK_H

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

static int FAILED(void) {
    if (failures) fprintf(stderr, "%d check(s) failed\n", failures);
    return failures != 0;
}

#endif
