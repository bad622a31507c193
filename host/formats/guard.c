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
 * device that calls no user callback and an address-space limit the caller
 * gives; its allocations and output are thrown away with it. When the
 * library fails cleanly in the child, its message is passed back and the
 * caller reports it without a second run. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include "host/formats/guard.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LCI_HAS_ASAN 1
#endif
#endif
#ifndef LCI_HAS_ASAN
#define LCI_HAS_ASAN 0
#endif

/* The process's mapped bytes now (/proc/self/statm), 0 when unknown. */
static uint64_t vm_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long long pages = 0;
    if (f) {
        if (fscanf(f, "%llu", &pages) != 1) pages = 0;
        fclose(f);
    }
    long ps = sysconf(_SC_PAGESIZE);
    return ps > 0 ? (uint64_t)pages * (uint64_t)ps : 0;
}

int lci_guarded(lc_device *dev, const char *env, uint64_t limit, lc_status (*fn)(lc_device *dev, void *ctx), void *ctx,
                lc_status *status, char *msg, size_t msgn)
{
    *status = LC_OK;
    if (msgn) msg[0] = 0;
    const char *e = env ? getenv(env) : NULL;
    if (e && !strcmp(e, "0")) return -1;
    uint64_t vm = vm_bytes();
    int fd[2];
    if (pipe(fd) != 0) return -1;
    pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]), close(fd[1]);
        return -1;
    }
    if (pid == 0) {
        close(fd[0]);
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, 1), dup2(null, 2);
        /* what the process maps now plus the limit: a damaged file made
           libhdf5 allocate 23 GB in 32-byte pieces until the kernel's OOM
           killer stopped it; past the limit its mallocs fail instead. Not
           under AddressSanitizer, whose shadow maps terabytes. */
#if !defined(__SANITIZE_ADDRESS__) && !LCI_HAS_ASAN
        if (vm && limit && vm + limit > vm) {
            struct rlimit rl = {(rlim_t)(vm + limit), (rlim_t)(vm + limit)};
            setrlimit(RLIMIT_AS, &rl);
        }
#else
        (void)vm, (void)limit;
#endif
        lc_device copy;
        if (dev) copy = *dev;
        else memset(&copy, 0, sizeof copy); /* lc_file_probe's counting has no device */
        copy.log = NULL, copy.log_user = NULL;
        copy.load_progress = NULL, copy.load_progress_user = NULL;
        copy.pool = NULL, copy.embree = NULL; /* threads do not survive fork */
        int32_t st = (int32_t)fn(&copy, ctx);
        char out[4 + LCI_MSG_MAX];
        memcpy(out, &st, 4);
        snprintf(out + 4, LCI_MSG_MAX, "%s", st != LC_OK ? lc_last_error() : "");
        size_t n = 4 + strlen(out + 4) + 1;
        if (write(fd[1], out, n) != (ssize_t)n) _exit(3);
        _exit(0);
    }
    close(fd[1]);
    char in[4 + LCI_MSG_MAX];
    size_t got = 0;
    for (ssize_t r; got < sizeof in && (r = read(fd[0], in + got, sizeof in - got)) != 0;) {
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) break;
        got += (size_t)r;
    }
    close(fd[0]);
    int st = 0;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR) return -1;
    if (WIFSIGNALED(st)) return WTERMSIG(st);
    if (got >= 5) {
        int32_t cs;
        memcpy(&cs, in, 4);
        in[sizeof in - 1] = 0;
        *status = (lc_status)cs;
        if (msgn) snprintf(msg, msgn, "%s", in + 4);
    }
    return 0;
}
