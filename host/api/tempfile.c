/* Temporary output files that signal handlers can remove: images
 * (host/api/image.c) and .rbf files (host/formats/rbf_write.c) are written
 * under a temporary name next to the target and renamed when complete. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>
#include "host/internal.h"

const char *lci_path_extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) return "";
    return dot;
}

/* Crash safety: the temporary files being written (images here, .rbf files
 * in host/formats/rbf_write.c), so that a program's
 * SIGINT/SIGTERM handler can remove them (lci_image_remove_temps). A slot is
 * claimed atomically, the name is built in the slot itself (mkstemps fills
 * it in place), and released after the rename or unlink. A signal between
 * the claim and mkstemps unlinks a name that does not exist yet: harmless. */
#define TEMP_SLOTS 16
static char temp_names[TEMP_SLOTS][LCI_TEMP_NAME];
static volatile sig_atomic_t temp_used[TEMP_SLOTS];

static int temp_claim(void)
{
    for (int i = 0; i < TEMP_SLOTS; i++) {
        sig_atomic_t zero = 0;
        if (__atomic_compare_exchange_n(&temp_used[i], &zero, 1, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) return i;
    }
    return -1;
}

void lci_temp_release(int slot)
{
    if (slot >= 0) __atomic_store_n(&temp_used[slot], 0, __ATOMIC_SEQ_CST);
}

/* Async-signal-safe (unlink only): removes every temporary image file this
 * process is writing. For signal handlers (tools/lanecast.c); the process
 * must not continue writing images afterwards. */
void lci_image_remove_temps(void);
void lci_image_remove_temps(void)
{
    for (int i = 0; i < TEMP_SLOTS; i++)
        if (__atomic_load_n(&temp_used[i], __ATOMIC_SEQ_CST)) unlink(temp_names[i]);
}

/* Creates a private temporary file next to the target with the same
 * extension (so OpenImageIO picks the same format): its name in out, its fd
 * returned, or -1 with errno set. *slot is its registration (release it with
 * lci_temp_release once the file is renamed or removed), -1 when all slots are
 * busy (more than TEMP_SLOTS concurrent writes: not removed on a signal). */
int lci_temp_file(const char *path, char *out, size_t n, int *slot)
{
    const char *ext = lci_path_extension(path);
    size_t stem = strlen(path) - strlen(ext);
    *slot = -1;
    int w = snprintf(out, n, "%.*s.lanecast-XXXXXX%s", (int)stem, path, ext);
    if (w <= 0 || (size_t)w >= n || (size_t)w >= LCI_TEMP_NAME) {
        errno = ENAMETOOLONG;
        return -1;
    }
    *slot = temp_claim();
    char *name = *slot >= 0 ? temp_names[*slot] : out;
    if (*slot >= 0) memcpy(name, out, (size_t)w + 1);
    int fd = mkstemps(name, (int)strlen(ext));
    if (name != out) memcpy(out, name, (size_t)w + 1);
    if (fd < 0) {
        int e = errno;
        lci_temp_release(*slot);
        *slot = -1;
        errno = e;
        return -1;
    }
    mode_t um = umask(0);
    umask(um);
    fchmod(fd, 0666 & ~um); /* the permissions an ordinary new file gets */
    return fd;
}


/* Test hook: LANECAST_TEST_WRITE_DELAY_MS=N holds the temporary file open
 * for N ms before writing it, so that a test can interrupt the write
 * (tests/test_cli_signals.sh): images and .rbf files. */
void lci_test_write_delay(void)
{
    const char *e = getenv("LANECAST_TEST_WRITE_DELAY_MS");
    long ms = e && *e ? atol(e) : 0;
    if (ms <= 0) return;
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}
