/* libFuzzer harness for one file format through the public API: the input
 * is written to a private temporary file and read with lc_volume_load and an
 * explicit format (FUZZ_FORMAT, set per executable in fuzz/meson.build).
 *
 * Input layout, chosen per harness at compile time:
 * - plain: the whole input is the file.
 * - FUZZ_OPTIONS_LINE: the first line (up to '\n', at most 255 bytes) holds
 *   load options "key=value key=value", the rest is the file (the raw
 *   formats, whose size, count and type come only from options).
 * - FUZZ_COMPANION: the first line holds the length L of the companion file
 *   in decimal; the next L bytes are the companion (e.g. the PSF topology of
 *   a DCD), the rest is the main file.
 *
 * Every failing load must leave a message (lc_last_error not empty); a
 * success is queried and destroyed. Anything else (a crash, a sanitizer
 * report, a leak, an empty message) is a finding. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <lanecast/lanecast.h>

#ifndef FUZZ_FORMAT
#error "FUZZ_FORMAT must name a format"
#endif
#ifndef FUZZ_EXT
#define FUZZ_EXT ".bin"
#endif

static lc_device *device;
static char dir[256], main_path[300], comp_path[300];

static void write_file(const char *path, const uint8_t *p, size_t n)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0) {
        perror(path);
        abort();
    }
    while (n > 0) {
        ssize_t k = write(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) {
            perror(path);
            abort();
        }
        p += k;
        n -= (size_t)k;
    }
    close(fd);
}

static void cleanup(void)
{
    unlink(main_path);
    unlink(comp_path);
    rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    /* libhdf5 in this process, not in the HDF5 reader's guard process
       (host/formats/guard.c): the fuzzer must see faults in lanecast's own
       code on those inputs too; libhdf5's own are triaged (docs/FUZZING.md) */
    setenv("LANECAST_HDF5_GUARD", "0", 1);
    setenv("LANECAST_NETCDF_GUARD", "0", 1);
    /* tmpfs when there is one: a file write per execution */
    const char *base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    snprintf(dir, sizeof dir, "%s/lanecast-fuzz-XXXXXX", base);
    if (!mkdtemp(dir)) {
        perror(dir);
        abort();
    }
    snprintf(main_path, sizeof main_path, "%s/input%s", dir, FUZZ_EXT);
    snprintf(comp_path, sizeof comp_path, "%s/companion", dir);
    atexit(cleanup);
    lc_device_desc dd = {.target = LC_TARGET_SCALAR, .threads = 1};
    if (lc_device_create(&dd, &device) != LC_OK) {
        fprintf(stderr, "fuzz: lc_device_create: %s\n", lc_last_error());
        abort();
    }
    return 0;
}

/* Splits the first line off: returns its length (without '\n') or -1. */
static long first_line(const uint8_t *d, size_t n, size_t max)
{
    for (size_t i = 0; i < n && i < max; i++)
        if (d[i] == '\n') return (long)i;
    return -1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lc_load_desc desc = {.format = FUZZ_FORMAT};
#ifdef FUZZ_OPTIONS_LINE
    char line[256];
    lc_option opts[8];
    int nopts = 0;
    long len = first_line(data, size, sizeof line - 1);
    if (len < 0) return -1; /* not in the layout: reject from the corpus */
    memcpy(line, data, (size_t)len);
    line[len] = '\0';
    for (char *tok = strtok(line, " "); tok && nopts < 8; tok = strtok(NULL, " ")) {
        char *eq = strchr(tok, '=');
        if (!eq) continue;
        *eq = '\0';
        opts[nopts].key = tok;
        opts[nopts].value = eq + 1;
        nopts++;
    }
    desc.options = opts;
    desc.noptions = nopts;
    data += len + 1;
    size -= (size_t)len + 1;
#endif
#ifdef FUZZ_COMPANION
    long len = first_line(data, size, 16);
    if (len <= 0) return -1;
    char num[17];
    memcpy(num, data, (size_t)len);
    num[len] = '\0';
    char *end;
    unsigned long clen = strtoul(num, &end, 10);
    if (*end || clen > size - (size_t)len - 1) return -1;
    write_file(comp_path, data + len + 1, clen);
    desc.companion = comp_path;
    data += (size_t)len + 1 + clen;
    size -= (size_t)len + 1 + clen;
#endif
    write_file(main_path, data, size);
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(device, main_path, &desc, &v);
    if (s == LC_OK) {
        lc_volume_info info;
        if (!v || lc_volume_get_info(v, &info) != LC_OK) {
            fprintf(stderr, "fuzz: lc_volume_load succeeded without a usable volume\n");
            abort();
        }
        lc_volume_destroy(v);
    } else {
        if (v) {
            fprintf(stderr, "fuzz: failed load left *out set\n");
            abort();
        }
        if (!lc_last_error()[0]) {
            fprintf(stderr, "fuzz: status %d without a message\n", (int)s);
            abort();
        }
        if (s == LC_ERROR_INTERNAL) {
            fprintf(stderr, "fuzz: internal error: %s\n", lc_last_error());
            abort();
        }
    }
    return 0;
}
