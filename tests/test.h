/* vergence — the test harness of every test executable: one executable per
 * module, one CTest test per case (`test_x NAME`). A case returns 0 on
 * success and fails loudly, printing the numbers it compared: CHECK ends
 * the case at the first failure, EXPECT and EXPECT_NEAR count failures and
 * go on (vg_test_failures; vg_test_main fails a case that counted any). */
#pragma once
#include <math.h>
#include <stdio.h>
#include <string.h>

#define CHECK(cond, ...)                                                              \
    do {                                                                              \
        if (!(cond)) {                                                                \
            fprintf(stderr, "%s:%d: check failed: %s\n    ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                             \
            fputc('\n', stderr);                                                      \
            return 1;                                                                 \
        }                                                                             \
    } while (0)

/* Failed EXPECTs of the running case (one counter for every file of an executable). */
__attribute__((weak)) int vg_test_failures;

#define EXPECT(cond, ...)                                                             \
    do {                                                                              \
        if (!(cond)) {                                                                \
            vg_test_failures++;                                                       \
            fprintf(stderr, "%s:%d: FAILED %s: ", __FILE__, __LINE__, #cond);         \
            fprintf(stderr, __VA_ARGS__);                                             \
            fputc('\n', stderr);                                                      \
        }                                                                             \
    } while (0)

#define EXPECT_NEAR(a, b, eps, ...)                                                   \
    do {                                                                              \
        double a_ = (a), b_ = (b);                                                    \
        if (!(fabs(a_ - b_) <= (eps))) {                                              \
            vg_test_failures++;                                                       \
            fprintf(stderr, "%s:%d: FAILED %s = %.7g, expected %.7g (eps %g): ",      \
                    __FILE__, __LINE__, #a, a_, b_, (double)(eps));                   \
            fprintf(stderr, __VA_ARGS__);                                             \
            fputc('\n', stderr);                                                      \
        }                                                                             \
    } while (0)

typedef struct vg_test_case {
    const char *name;
    int (*fn)(void);
} vg_test_case;

/* Runs the case named argv[1], or every case without an argument. */
static inline int vg_test_main(int argc, char **argv, const vg_test_case *cases, int n)
{
    int failed = 0, ran = 0;
    for (int i = 0; i < n; i++) {
        if (argc > 1 && strcmp(argv[1], cases[i].name) != 0)
            continue;
        ran++;
        vg_test_failures = 0;
        int r = cases[i].fn() || vg_test_failures;
        printf("%s: %s\n", cases[i].name, r ? "FAILED" : "ok");
        failed += r != 0;
    }
    if (!ran) {
        fprintf(stderr, "no test case named '%s'\n", argc > 1 ? argv[1] : "");
        return 2;
    }
    return failed ? 1 : 0;
}
#define VG_TEST_COUNT(cases) ((int)(sizeof(cases) / sizeof((cases)[0])))
