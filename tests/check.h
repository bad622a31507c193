/* Tiny check macros shared by the C tests: print every check, count failures. */
#ifndef LC_TEST_CHECK_H
#define LC_TEST_CHECK_H

#include <stdio.h>

static int check_failures;

#define CHECK(cond, ...)                                                                                             \
    do {                                                                                                             \
        int ok_ = (cond) ? 1 : 0;                                                                                    \
        printf("%s ", ok_ ? "ok  " : "FAIL");                                                                        \
        printf(__VA_ARGS__);                                                                                         \
        printf("\n");                                                                                                \
        if (!ok_) check_failures++;                                                                                  \
    } while (0)

/* Like CHECK but prints only failures, with file and line: for tests that run
 * thousands of checks. */
#define CHECK_QUIET(cond, ...)                                                                                       \
    do {                                                                                                             \
        if (!(cond)) {                                                                                               \
            check_failures++;                                                                                        \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                                                              \
            printf(__VA_ARGS__);                                                                                     \
            printf("\n");                                                                                            \
        }                                                                                                            \
    } while (0)

static inline int check_summary(const char *suite)
{
    printf("%s: %s (%d failures)\n", suite, check_failures ? "FAIL" : "PASS", check_failures);
    return check_failures ? 1 : 0;
}

#endif
