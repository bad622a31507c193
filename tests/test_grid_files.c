/* Volume files through lc_volume_load: NRRD (attached, detached, gzip, big
 * endian), MetaImage, raw-volume (format named, text options); format and
 * kind options (type, spacing, origin, size, endian, brick, layout); bad
 * headers, files and options give one clear error (naming the key) and no
 * grid; lc_file_probe. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <unistd.h>
#include "gzip_stored.h"
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

/* A gzip file of the data (stored blocks: no zlib needed), cut after
 * truncate_to bytes when that is non-zero. */
static void put_gz(const char *name, const void *data, size_t n, size_t truncate_to)
{
    gzs_write(path(name), data, n);
    if (truncate_to && truncate(path(name), (off_t)truncate_to) != 0) printf("cannot truncate %s\n", name);
}

/* 1 if this build has the optional feature (lanecast formats lists them). */
static int have(const char *feature)
{
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) == LC_OK && !strcmp(f.name, feature)) return f.available;
    }
    return 0;
}

/* lc_volume_load with a format name (NULL = detect) and n options */
static lc_status load(lc_device *dev, const char *file, const char *format, const lc_option *o, int n, lc_volume **out)
{
    lc_load_desc d = {.format = format, .options = o, .noptions = n};
    return lc_volume_load(dev, path(file), &d, out);
}
#define NOPT(a) (int)(sizeof(a) / sizeof((a)[0]))

/* expect failure with a message containing `what`, and no grid */
static void bad(lc_device *dev, const char *file, const char *format, const lc_option *o, int n, const char *what)
{
    lc_volume *g = (lc_volume *)1;
    lc_status s = load(dev, file, format, o, n, &g);
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

    /* raw data has no header: its format is named, its size and type are options */
    const char *good[] = {"ok.nhdr", "be.nhdr", "gz.nhdr", "att.nrrd", "ok.mhd", "v.raw", "vbe.raw"};
    const lc_option raw[] = {{"size", "5,4,3"}, {"type", "uint16"}};
    const lc_option raw_be[] = {{"size", "5,4,3"}, {"type", "uint16"}, {"endian", "big"}};
    for (int i = 0; i < 7; i++) {
        lc_volume *g = NULL;
        lc_status s = load(dev, good[i], i >= 5 ? "raw-volume" : NULL, i == 6 ? raw_be : raw, i == 6 ? 3 : i == 5 ? 2 : 0, &g);
        if (i == 2 && !have("zlib")) { /* compiled out: one line naming the package */
            CHECK_QUIET(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "zlib1g-dev"), "%s without zlib: %s",
                        good[i], lc_last_error());
            continue;
        }
        CHECK_QUIET(s == LC_OK, "%s: %s", good[i], lc_last_error());
        if (!g) continue;
        lc_grid_info in;
        CHECK_QUIET(lc_volume_kind(g) == LC_KIND_GRID && lc_grid_get_info(g, &in) == LC_OK, "%s: a grid", good[i]);
        uint16_t mx = 0, mn = 65535;
        for (int k = 0; k < N; k++) mx = le[k] > mx ? le[k] : mx, mn = le[k] < mn ? le[k] : mn;
        CHECK_QUIET(in.size[0] == NX && in.size[1] == NY && in.size[2] == NZ && in.type == LC_VALUE_UINT16, "%s: info", good[i]);
        CHECK_QUIET(in.value_min == mn && in.value_max == mx, "%s: range %g..%g, expected %d..%d (endianness?)", good[i],
              (double)in.value_min, (double)in.value_max, mn, mx);
        if (i < 3 || i == 4) CHECK_QUIET(in.spacing.y == 2 && in.spacing.z == 3, "%s: spacing", good[i]);
        lc_volume_destroy(g);
    }
    /* the format's options (type, spacing, origin) and the kind's (brick, layout) */
    {
        const lc_option o[] = {{"spacing", "0.5,0.25,2"}, {"origin", "1,-2,3.5"}, {"brick", "2"}, {"layout", "linear"},
                               {"type", "uint16"}};
        lc_volume *g = NULL;
        lc_status s = load(dev, "ok.nhdr", NULL, o, NOPT(o), &g);
        lc_grid_info in;
        memset(&in, 0, sizeof in);
        if (s == LC_OK) lc_grid_get_info(g, &in);
        CHECK_QUIET(s == LC_OK && in.spacing.x == 0.5f && in.spacing.y == 0.25f && in.spacing.z == 2.0f &&
                        in.origin.x == 1.0f && in.origin.y == -2.0f && in.origin.z == 3.5f && in.brick == 2 &&
                        in.layout == LC_LAYOUT_LINEAR && in.bounds.hi.x == 1.0f + 4 * 0.5f,
                    "ok.nhdr with options: %s (spacing %g,%g,%g origin %g,%g,%g brick %d layout %d)",
                    s == LC_OK ? "loaded" : lc_last_error(), (double)in.spacing.x, (double)in.spacing.y,
                    (double)in.spacing.z, (double)in.origin.x, (double)in.origin.y, (double)in.origin.z, in.brick,
                    (int)in.layout);
        lc_volume_destroy(g);
        const lc_option ob[] = {{"layout", "bricked"}};
        g = NULL;
        s = load(dev, "ok.mhd", "metaimage", ob, 1, &g);
        if (s == LC_OK) lc_grid_get_info(g, &in);
        CHECK_QUIET(s == LC_OK && in.layout == LC_LAYOUT_BRICKED, "ok.mhd layout bricked: %s",
                    s == LC_OK ? "loaded" : lc_last_error());
        lc_volume_destroy(g);
    }
    /* lc_file_probe: magic, extension (through .gz), a named format */
    {
        static const struct { const char *file, *format, *want; int gzip; } pr[] = {
            {"ok.nhdr", NULL, "nrrd", 0}, {"att.nrrd", NULL, "nrrd", 0}, {"ok.mhd", NULL, "metaimage", 0},
            {"v.raw", NULL, "raw-volume", 0}, {"v.raw.gz", NULL, "raw-volume", 1}, {"v.raw", "raw-volume", "raw-volume", 0}};
        for (size_t i = 0; i < sizeof pr / sizeof pr[0]; i++) {
            lc_file_info fi;
            memset(&fi, 0, sizeof fi);
            lc_load_desc d = {.format = pr[i].format};
            lc_status s = lc_file_probe(dev, path(pr[i].file), &d, &fi);
            CHECK_QUIET(s == LC_OK && fi.format && !strcmp(fi.format, pr[i].want) && fi.kind == LC_KIND_GRID &&
                            fi.gzip == pr[i].gzip && fi.frames == 1,
                        "lc_file_probe %s: %s, format %s, kind %d, gzip %d", pr[i].file, lc_status_string(s),
                        fi.format ? fi.format : "(null)", (int)fi.kind, fi.gzip);
        }
    }
    printf("bad files:\n");
    put("short.raw", le, sizeof le - 2);
    snprintf(buf, sizeof buf, h, "raw", "little", "short.raw");
    put_str("short.nhdr", buf);
    bad(dev, "short.nhdr", NULL, NULL, 0, "need 120");
    put_str("type.nhdr", "NRRD0004\ntype: double\ndimension: 3\nsizes: 5 4 3\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "type.nhdr", NULL, NULL, 0, "type.nhdr:2: type \"double\"");
    bad(dev, "trunc.nhdr", NULL, NULL, 0, have("zlib") ? "truncated" : "zlib1g-dev");
    put_str("ovf.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "ovf.nhdr", NULL, NULL, 0, "overflow");
    put_str("ovf2.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4294967296 4294967296 2\nencoding: raw\ndata file: v.raw\n");
    bad(dev, "ovf2.nhdr", NULL, NULL, 0, "size");
    put_str("magic.nhdr", "NRRX\n");
    bad(dev, "magic.nhdr", NULL, NULL, 0, "magic");
    put_str("type.mhd", "NDims = 3\nDimSize = 5 4 3\nElementType = MET_DOUBLE\nElementDataFile = v.raw\n");
    bad(dev, "type.mhd", NULL, NULL, 0, "type.mhd:3: ElementType");
    const lc_option raw_bad[] = {{"size", "5,4,4"}, {"type", "uint16"}};
    bad(dev, "v.raw", "raw-volume", raw_bad, NOPT(raw_bad), "need 160");
    bad(dev, "v.raw", "raw-volume", NULL, 0, "needs its sizes");
    const lc_option raw_notype[] = {{"size", "5,4,3"}};
    bad(dev, "v.raw", "raw-volume", raw_notype, NOPT(raw_notype), "type");
    bad(dev, "missing.nhdr", NULL, NULL, 0, "cannot open");
    /* options: an unknown key, a key of another format or kind, bad values, each named */
    const lc_option unknown[] = {{"size", "5,4,3"}, {"type", "uint16"}, {"frobnicate", "1"}};
    bad(dev, "v.raw", "raw-volume", unknown, NOPT(unknown), "'frobnicate'");
    const lc_option particle_key[] = {{"radius", "1"}};
    bad(dev, "ok.nhdr", NULL, particle_key, NOPT(particle_key), "'radius'");
    const lc_option raw_key[] = {{"size", "5,4,3"}};
    bad(dev, "ok.nhdr", NULL, raw_key, NOPT(raw_key), "'size'");
    const lc_option bad_type[] = {{"size", "5,4,3"}, {"type", "float64"}};
    bad(dev, "v.raw", "raw-volume", bad_type, NOPT(bad_type), "type = 'float64'");
    const lc_option bad_size[] = {{"size", "5,4"}, {"type", "uint16"}};
    bad(dev, "v.raw", "raw-volume", bad_size, NOPT(bad_size), "size = '5,4'");
    const lc_option bad_endian[] = {{"size", "5,4,3"}, {"type", "uint16"}, {"endian", "middle"}};
    bad(dev, "v.raw", "raw-volume", bad_endian, NOPT(bad_endian), "middle");
    const lc_option bad_spacing[] = {{"spacing", "1,x,1"}};
    bad(dev, "ok.nhdr", NULL, bad_spacing, NOPT(bad_spacing), "spacing = '1,x,1'");
    const lc_option bad_brick[] = {{"brick", "3"}};
    bad(dev, "ok.nhdr", NULL, bad_brick, NOPT(bad_brick), "brick 3");
    const lc_option bad_layout[] = {{"layout", "morton"}};
    bad(dev, "ok.nhdr", NULL, bad_layout, NOPT(bad_layout), "layout = 'morton'");
    const lc_option other_type[] = {{"type", "float32"}};
    bad(dev, "ok.nhdr", NULL, other_type, NOPT(other_type), "type");
    bad(dev, "ok.nhdr", "nosuch", NULL, 0, "'nosuch'");
    bad(dev, "ok.nhdr", "xyz", NULL, 0, "ok.nhdr");
    lc_device_destroy(dev);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    printf("%s: %d failure(s)\n", check_failures ? "FAIL" : "ok", check_failures);
    return check_failures ? 1 : 0;
}
