/* The C tests' checks: a macro that reports a failed condition with its place and counts it,
 * and the exit status that sums them up. */
#ifndef SMOOTHTRI_TEST_CHECK_H
#define SMOOTHTRI_TEST_CHECK_H

#include <stdio.h>

static int failures = 0;

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);        \
            failures++;                                                                    \
        }                                                                                  \
    } while (0)

/* The program's exit status once every check ran: 1 after a failed check (saying how many on
 * stderr), else 0 after printing `passed` and a newline (nothing when it is NULL). */
static inline int check_exit_status(const char *passed) {
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    if (passed != NULL) printf("%s\n", passed);
    return 0;
}

#endif
