/* Running a third-party reader in a child process first (host/formats/guard.c). */
#ifndef LC_FORMATS_GUARD_H
#define LC_FORMATS_GUARD_H

#include "host/internal.h"

/* Runs fn(dev_copy, ctx) in a forked child whose stdout and stderr go to
 * /dev/null and whose device copy has no log or progress callback, and
 * waits for it. Returns 0 when the child ended normally (whatever fn
 * returned), the signal number that killed it, or -1 when no child could be
 * run (the caller then goes on unguarded). env: an environment variable
 * that, set to 0, turns the guard off (returns -1 at once). */
int lci_guarded(lc_device *dev, const char *env, void (*fn)(lc_device *dev, void *ctx), void *ctx);

#endif
