/* Running a third-party reader in a child process first (host/formats/guard.c). */
#ifndef LC_FORMATS_GUARD_H
#define LC_FORMATS_GUARD_H

#include <stddef.h>
#include <stdint.h>
#include "host/internal.h"

/* Runs fn(dev_copy, ctx) in a forked child whose stdout and stderr go to
 * /dev/null, whose device copy has no log or progress callback and whose
 * address space may grow by at most `limit` bytes, and waits for it.
 * Returns the signal number that killed the child; 0 when it ended
 * normally, with fn's status in *status and the child's lc_last_error()
 * in msg when that status is an error; or -1 when no child could be run
 * (the caller then goes on unguarded). env: an environment variable that,
 * set to 0, turns the guard off (returns -1 at once). */
int lci_guarded(lc_device *dev, const char *env, uint64_t limit, lc_status (*fn)(lc_device *dev, void *ctx), void *ctx,
                lc_status *status, char *msg, size_t msgn);

#endif
