/* A guard process for libraries that crash on damaged files. Debian 12's
 * libhdf5 1.10.8 trusts sizes and layouts a file declares: fuzzing found it
 * dereferencing NULL after a failed allocation for a declared local heap,
 * over-reading attribute names and overrunning a stack buffer for a declared
 * bit width (docs/FUZZING.md). lanecast cannot fix or predict those from
 * outside, so a reader runs the library once in a child process: when the
 * child dies of a signal the load fails with a message instead of taking
 * the caller's process down. The cost is one more pass of the library over
 * the file (served from the page cache on the second pass).
 *
 * The child runs only the calling thread's code (fork), with a copy of the
 * device that calls no user callback; its allocations and output are
 * thrown away with it. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "host/formats/guard.h"

int lci_guarded(lc_device *dev, const char *env, void (*fn)(lc_device *dev, void *ctx), void *ctx)
{
    const char *e = env ? getenv(env) : NULL;
    if (e && !strcmp(e, "0")) return -1;
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, 1), dup2(null, 2);
        lc_device copy = *dev;
        copy.log = NULL, copy.log_user = NULL;
        copy.load_progress = NULL, copy.load_progress_user = NULL;
        copy.pool = NULL, copy.embree = NULL; /* threads do not survive fork */
        fn(&copy, ctx);
        _exit(0);
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR) return -1;
    if (WIFSIGNALED(st)) return WTERMSIG(st);
    return 0;
}
