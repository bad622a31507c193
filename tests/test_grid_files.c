/* Volume files: NRRD (attached, detached, gzip, big endian), MetaImage, raw;
 * bad headers and files give one clear error and no grid. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>
#include "lanecast/lanecast.h"

#include "check.h"

static char dir[256];

static void put(const char *name, const void *data, size_t n)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    fwrite(data, 1, n, f);
    fclose(f);
}
static void put_str(const char *name, const char *s) { put(name, s, strlen(s)); }
static const char *path(const char *name)
{
    static char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return p;
}

static void put_gz(const char *name, const void *data, size_t n, size_t truncate_to)
{
    uLongf cap = compressBound(n) + 64;
    unsigned char *buf = malloc(cap);
    z_stream z;
    memset(&z, 0, sizeof z);
    deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY); /* gzip wrapper */
    z.next_in = (unsigned char *)data, z.avail_in = (uInt)n, z.next_out = buf, z.avail_out = (uInt)cap;
    deflate(&z, Z_FINISH);
    size_t len = cap - z.avail_out;
    deflateEnd(&z);
    put(name, buf, truncate_to && truncate_to < len ? truncate_to : len);
    free(buf);
}

/* expect failure with a message containing `what`, and no grid */
static void bad(lc_device *dev, const char *file, const lc_grid_load_options *o, const char *what)
{
    lc_grid *g = (lc_grid *)1;
    lc_status s = lc_grid_load(dev, path(file), o, &g);
    const char *m = lc_last_error();
    CHECK_QUIET(s != LC_OK && g == NULL, "%s: expected an error", file);
    CHECK_QUIET(strstr(m, what) != NULL && strchr(m, '\n') == NULL, "%s: message \"%s\" lacks \"%s\"", file, m, what);
    printf("  %-16s -> %s\n", file, m);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/lc_grid_files_%d", (int)getpid());
    char cmd[600];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", dir);
    if (system(cmd) != 0) return 1;
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.threads = 1}, &dev) != LC_OK) return 1;
    enum { NX = 5, NY = 4, NZ = 3, N = NX * NY * NZ };
    uint16_t le[N], be[N];
    for (int i = 0; i < N; i++) {
        le[i] = (uint16_t)(i * 997 % 4096);
        be[i] = (uint16_t)((le[i] >> 8) | (le[i] << 8));
    }
    put("v.raw", le, sizeof le);
    put("vbe.raw", be, sizeof be);
    put_gz("v.raw.gz", le, sizeof le, 0);
    put_gz("trunc.raw.gz", le, sizeof le, 40);
    const char *h = "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 5 4 3\nspacings: 1 2 3\nencoding: %s\nendian: %s\ndata file: %s\n";
    char buf[1024];
    snprintf(buf, sizeof buf, h, "raw", "little", "v.raw");
    put_str("ok.nhdr", buf);
    snprintf(buf, sizeof buf, h, "raw", "big", "vbe.raw");
    put_str("be.nhdr", buf);
    snprintf(buf, sizeof buf, h, "gzip", "little", "v.raw.gz");
    put_str("gz.nhdr", buf);
    snprintf(buf, sizeof buf, h, "gzip", "little", "trunc.raw.gz");
    put_str("trunc.nhdr", buf);
    /* attached data */
    const char *ah = "NRRD0004\ntype: unsigned short\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: raw\n\n";
    unsigned char att[1024];
    memcpy(att, ah, strlen(ah));
    memcpy(att + strlen(ah), le, sizeof le);
    put("att.nrrd", att, strlen(ah) + sizeof le);
    put_str("ok.mhd", "NDims = 3\nDimSize = 5 4 3\nElementSpacing = 1 2 3\nElementType = MET_USHORT\nElementDataFile = v.raw\n");

    const char *good[] = {"ok.nhdr", "be.nhdr", "gz.nhdr", "att.nrrd", "ok.mhd", "v.raw"};
    lc_grid_load_options raw = {.size = {NX, NY, NZ}, .type = LC_VALUE_UINT16};
    for (int i = 0; i < 6; i++) {
        lc_grid *g = NULL;
        lc_status s = lc_grid_load(dev, path(good[i]), i == 5 ? &raw : NULL, &g);
        CHECK_QUIET(s == LC_OK, "%s: %s", good[i], lc_last_error());
        if (!g) continue;
        lc_grid_info in;
        lc_grid_get_info(g, &in);
        uint16_t mx = 0, mn = 65535;
        for (int k = 0; k < N; k++) mx = le[k] > mx ? le[k] : mx, mn = le[k] < mn ? le[k] : mn;
        CHECK_QUIET(in.size[0] == NX && in.size[1] == NY && in.size[2] == NZ && in.type == LC_VALUE_UINT16, "%s: info", good[i]);
        CHECK_QUIET(in.value_min == mn && in.value_max == mx, "%s: range %g..%g, expected %d..%d (endianness?)", good[i],
              (double)in.value_min, (double)in.value_max, mn, mx);
        if (i < 3 || i == 4) CHECK_QUIET(in.spacing.y == 2 && in.spacing.z == 3, "%s: spacing", good[i]);
        lc_grid_destroy(g);
    }
    printf("bad files:\n");
    put("short.raw", le, sizeof le - 2);
    snprintf(buf, sizeof buf, h, "raw", "little", "short.raw");
    put_str("short.nhdr", buf);
    bad(dev, "short.nhdr", NULL, "need 120");
    put_str("type.nhdr", "NRRD0004\ntype: double\ndimension: 3\nsizes: 5 4 3\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "type.nhdr", NULL, "type.nhdr:2: type \"double\"");
    bad(dev, "trunc.nhdr", NULL, "truncated");
    put_str("ovf.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "ovf.nhdr", NULL, "overflow");
    put_str("ovf2.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4294967296 4294967296 2\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "ovf2.nhdr", NULL, "size");
    put_str("magic.nhdr", "NRRX\n");
    bad(dev, "magic.nhdr", NULL, "magic");
    put_str("type.mhd", "NDims = 3\nDimSize = 5 4 3\nElementType = MET_DOUBLE\nElementDataFile = v.raw\n");
    bad(dev, "type.mhd", NULL, "type.mhd:3: ElementType");
    lc_grid_load_options raw_bad = {.size = {NX, NY, NZ + 1}, .type = LC_VALUE_UINT16};
    bad(dev, "v.raw", &raw_bad, "need 160");
    bad(dev, "v.raw", NULL, "needs its sizes");
    bad(dev, "missing.nhdr", NULL, "cannot open");
    lc_device_destroy(dev);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    printf("%s: %d failure(s)\n", check_failures ? "FAIL" : "ok", check_failures);
    return check_failures ? 1 : 0;
}
