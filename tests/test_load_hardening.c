/* Library side of the loader hardening (issue 13, docs/HARDENING.md), through
 * the public API: the max_memory load option (refusal naming needed and
 * allowed bytes, bad values), data files that are not regular files, header
 * offsets, streamed gzip (several members, trailing bytes), and the
 * transfer-function messages for empty and truncated JSON.
 * usage: test_load_hardening BUILD_DIR */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "check.h"
#include "lanecast/lanecast.h"

static char dir[4096];

static const char *put(const char *name, const void *data, size_t n)
{
    static char path[8][4200];
    static int k;
    char *p = path[k++ % 8];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    if (f) fwrite(data, 1, n, f), fclose(f);
    return p;
}

static const char *nhdr(const char *name, const char *extra, const char *data)
{
    char h[512];
    int n = snprintf(h, sizeof h, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n%sdata file: %s\n\n",
                     extra, data);
    return put(name, h, (size_t)n);
}

/* Loads path with the options; status and whether the message holds want. */
static void expect(lc_device *dev, const char *what, const char *path, const lc_option *opt, int nopt, lc_status want,
                   const char *words)
{
    lc_load_desc d = {.options = opt, .noptions = nopt};
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, path, &d, &v);
    int ok = s == want && (s == LC_OK ? v != NULL : v == NULL && strstr(lc_last_error(), words) != NULL);
    CHECK(ok, "%s: status %d (want %d): %s", what, (int)s, (int)want, s == LC_OK ? "loaded" : lc_last_error());
    lc_volume_destroy(v);
}

int main(int argc, char **argv)
{
    snprintf(dir, sizeof dir, "%s/load_hardening_XXXXXX", argc > 1 ? argv[1] : "/tmp");
    if (!mkdtemp(dir)) return printf("mkdtemp failed\n"), 1;
    lc_device *dev;
    lc_device_desc dd = {.threads = 1};
    if (lc_device_create(&dd, &dev) != LC_OK) return printf("lc_device_create: %s\n", lc_last_error()), 1;

    const unsigned char vox[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    put("d8", vox, 8);
    const char *good = nhdr("good.nhdr", "", "d8");
    expect(dev, "control", good, NULL, 0, LC_OK, "");

    /* the memory limit: 8 voxels + 64 bytes of padding = 72 bytes */
    lc_option m16 = {"max_memory", "16"}, m1k = {"max_memory", "1K"}, m72 = {"max_memory", "72"}, m71 = {"max_memory", "71"};
    expect(dev, "max_memory 16 refuses 72 bytes", good, &m16, 1, LC_ERROR_OUT_OF_MEMORY, "need 72 bytes, more than the memory limit of 16 bytes");
    expect(dev, "max_memory 71 refuses (the limit is exact)", good, &m71, 1, LC_ERROR_OUT_OF_MEMORY, "limit of 71 bytes");
    expect(dev, "max_memory 72 allows", good, &m72, 1, LC_OK, "");
    expect(dev, "max_memory 1K allows", good, &m1k, 1, LC_OK, "");
    const char *bad[] = {"0", "-1", "abc", "1Q", "", "1e400"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        lc_option o = {"max_memory", bad[i]};
        char what[64];
        snprintf(what, sizeof what, "max_memory '%s' refused", bad[i]);
        expect(dev, what, good, &o, 1, LC_ERROR_INVALID_ARGUMENT, "option max_memory");
    }
    /* the limit is per load: the next load without it succeeds */
    expect(dev, "limit does not stick to the device", good, NULL, 0, LC_OK, "");
    /* particles: raw count over the limit fails before reading */
    float xyz[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    const char *f32 = put("p.f32", xyz, sizeof xyz);
    lc_option praw[3] = {{"count", "3"}, {"radius", "1"}, {"max_memory", "20"}};
    lc_load_desc pd = {.format = "raw-particles", .options = praw, .noptions = 3};
    lc_volume *pv = NULL;
    lc_status s = lc_volume_load(dev, f32, &pd, &pv);
    CHECK(s == LC_ERROR_OUT_OF_MEMORY && strstr(lc_last_error(), "3 particles need"), "raw particles over max_memory: %s",
          lc_last_error());
    lc_volume_destroy(pv);
    pd.noptions = 2;
    s = lc_volume_load(dev, f32, &pd, &pv);
    CHECK(s == LC_OK, "control: raw particles without the limit: %s", s ? lc_last_error() : "loaded");
    lc_volume_destroy(pv);

    /* XTC (uncompressed, 3 atoms: 36 bytes of positions) and TRR: the memory
       limit before the positions are allocated, a header whose atom count
       the file cannot hold refused before any allocation */
    unsigned char xtc[92] = {0};
    uint32_t xh[14] = {1995, 3, 0, 0, 0x3f800000u, 0, 0, 0, 0x3f800000u, 0, 0, 0, 0x3f800000u, 3};
    for (int i = 0; i < 23; i++) {
        uint32_t v = i < 14 ? xh[i] : 0x3f000000u * (i % 2); /* 0.5 or 0 nm */
        xtc[4 * i] = (unsigned char)(v >> 24), xtc[4 * i + 1] = (unsigned char)(v >> 16);
        xtc[4 * i + 2] = (unsigned char)(v >> 8), xtc[4 * i + 3] = (unsigned char)v;
    }
    const char *x3 = put("three.xtc", xtc, sizeof xtc);
    lc_option r1 = {"radius", "1"}, xm[2] = {{"radius", "1"}, {"max_memory", "20"}};
    expect(dev, "XTC control (3 atoms)", x3, &r1, 1, LC_OK, "");
    expect(dev, "XTC over max_memory", x3, xm, 2, LC_ERROR_OUT_OF_MEMORY, "more than the memory limit of 20 bytes");
    xtc[7] = xtc[55] = 9; /* 9 atoms declared, 3 stored */
    expect(dev, "XTC atom count past the file", put("lying.xtc", xtc, sizeof xtc), &r1, 1, LC_ERROR_FORMAT,
           "the file ends inside frame 0 (108 bytes needed, 36 left)");

    /* data files that are not regular files */
    char sub[4200];
    snprintf(sub, sizeof sub, "%s/sub", dir);
    mkdir(sub, 0700);
    expect(dev, "data file is a directory", nhdr("dir.nhdr", "", "sub"), NULL, 0, LC_ERROR_IO, "/sub: is a directory");
    char fifo[4200];
    snprintf(fifo, sizeof fifo, "%s/fifo", dir);
    if (mkfifo(fifo, 0600) == 0) {
        expect(dev, "data file is a FIFO (no hang)", nhdr("fifo.nhdr", "", "fifo"), NULL, 0, LC_ERROR_IO, "is a FIFO");
        expect(dev, "input is a FIFO (no hang)", fifo, NULL, 0, LC_ERROR_IO, "is a FIFO");
    }
    expect(dev, "input is a directory", sub, NULL, 0, LC_ERROR_IO, "is a directory");

    /* header offsets */
    unsigned char d12[12] = {'x', 'x', 'x', 'x', 1, 2, 3, 4, 5, 6, 7, 8};
    put("d12", d12, 12);
    expect(dev, "byte skip -1: data at the end", nhdr("s1.nhdr", "byte skip: -1\n", "d12"), NULL, 0, LC_OK, "");
    expect(dev, "byte skip -2", nhdr("s2.nhdr", "byte skip: -2\n", "d12"), NULL, 0, LC_ERROR_FORMAT, ":6: byte skip");
    expect(dev, "byte skip abc", nhdr("s3.nhdr", "byte skip: abc\n", "d12"), NULL, 0, LC_ERROR_FORMAT, ":6: byte skip");
    expect(dev, "byte skip 2^63-1", nhdr("s4.nhdr", "byte skip: 9223372036854775807\n", "d12"), NULL, 0, LC_ERROR_FORMAT,
           ":6: byte skip");
    expect(dev, "byte skip past the file", nhdr("s5.nhdr", "byte skip: 13\n", "d12"), NULL, 0, LC_ERROR_FORMAT,
           "shorter than the header's offset 13");
    expect(dev, "spacings 0 0 0", nhdr("z.nhdr", "spacings: 0 0 0\n", "d8"), NULL, 0, LC_ERROR_FORMAT, ":6: spacings");

    /* the transfer-function messages (JSON TFs need json-c) */
    lc_tf *tf = NULL;
    int json = 0;
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info fi;
        if (lc_feature_get(i, &fi) == LC_OK && !strcmp(fi.name, "json")) json = fi.available;
    }
    if (!json) {
        printf("skip: the TF JSON checks (built without json-c)\n");
        lc_device_destroy(dev);
        return check_summary("test_load_hardening");
    }
    s = lc_tf_parse(dev, "", "t.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "t.json: empty file") != NULL, "empty TF: %s", lc_last_error());
    s = lc_tf_parse(dev, " \n ", "t.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "only white space") != NULL, "blank TF: %s", lc_last_error());
    s = lc_tf_parse(dev, "{\"range\": [0, 1], \"opacity\": [[0, 0], [1", "t.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "inside an array") != NULL, "TF cut in an array: %s",
          lc_last_error());
    s = lc_tf_parse(dev, "{\"range\": [0, 1], \"na", "t.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "inside a string") != NULL, "TF cut in a string: %s",
          lc_last_error());
    s = lc_tf_load(dev, sub, &tf);
    CHECK(s == LC_ERROR_IO && strstr(lc_last_error(), "is a directory") != NULL, "TF file is a directory: %s",
          lc_last_error());
    lc_tf_destroy(tf);
    lc_device_destroy(dev);
    return check_summary("test_load_hardening");
}
