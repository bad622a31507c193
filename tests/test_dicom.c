/* DICOM series (host/formats/dicom.c) against files a third-party writer
 * made: tests/dicom_write.py writes them with pydicom (compressed copies by
 * GDCM's gdcmconv) into the build folder, with the grids they must load to
 * (expect.txt, NAME.raw: computed there from DICOM's geometry rules, not by
 * lanecast). Checked: voxel values bit for bit (after rescale), type, sizes,
 * spacing and origin, warnings (oblique only where expected), the malformed
 * variants' messages (the file and what was wrong), the series listing, and
 * in a build without GDCM the one line naming libgdcm-dev.
 *
 * usage: test_dicom BUILD_DIR SOURCE_DIR [LANECAST] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include "check.h"
#include "host/formats/format.h"
#include "host/internal.h"
#include "host/kinds/grid.h"

static char warnings[8192];

static void on_log(void *user, lc_log_level level, const char *msg)
{
    (void)user;
    if (level == LC_LOG_WARNING && strlen(warnings) + strlen(msg) + 2 < sizeof warnings)
        strcat(warnings, msg), strcat(warnings, "\n");
}

/* INPUT "a:b:c" relative to dir: path = dir/a, and with several, option
 * files = every path, one per line. opt "-" or key=value. */
typedef struct req {
    char path[2048], files[16384], key[64], value[256];
    lc_option o[2];
    lc_load_desc d;
} req;

static void make_req(req *r, const char *dir, const char *input, const char *opt)
{
    memset(r, 0, sizeof *r);
    int n = 0;
    char buf[8192];
    snprintf(buf, sizeof buf, "%s", input);
    for (char *t = strtok(buf, ":"); t; t = strtok(NULL, ":")) {
        if (!n) snprintf(r->path, sizeof r->path, "%s/%s", dir, t);
        snprintf(r->files + strlen(r->files), sizeof r->files - strlen(r->files), "%s/%s\n", dir, t);
        n++;
    }
    int k = 0;
    if (n > 1) r->o[k++] = (lc_option){"files", r->files};
    const char *eq = strchr(opt, '=');
    if (eq) {
        snprintf(r->key, sizeof r->key, "%.*s", (int)(eq - opt), opt);
        snprintf(r->value, sizeof r->value, "%s", eq + 1);
        r->o[k++] = (lc_option){r->key, r->value};
    }
    r->d.options = r->o;
    r->d.noptions = k;
}

static void *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *p = malloc((size_t)len + 1);
    *n = p && fread(p, 1, (size_t)len, f) == (size_t)len ? (size_t)len : 0;
    fclose(f);
    return p;
}

static void check_ok(lc_device *dev, const char *dir, char *line)
{
    char name[64], input[4096], opt[256], type[16], warn[64];
    int sz[3];
    double sp[3], org[3];
    if (sscanf(line, "ok %63s %4095s %255s %15s %d %d %d %lf %lf %lf %lf %lf %lf %63s", name, input, opt, type, &sz[0],
               &sz[1], &sz[2], &sp[0], &sp[1], &sp[2], &org[0], &org[1], &org[2], warn) != 14) {
        CHECK(0, "expect.txt line: %s", line);
        return;
    }
    req r;
    make_req(&r, dir, input, opt);
    warnings[0] = 0;
    lci_loaded l;
    const char *fmt = NULL;
    lc_status s = lci_read_grid(dev, r.path, &r.d, &fmt, &l);
    CHECK(s == LC_OK, "%s: %s loads (%s)", name, input, s == LC_OK ? "ok" : lc_last_error());
    if (s != LC_OK) return;
    const lc_grid_desc *d = l.desc;
    static const char *const tn[] = {"", "uint8", "uint16", "int16", "float32"};
    CHECK(!strcmp(fmt, "dicom") && d->type >= 1 && d->type <= 4 && !strcmp(tn[d->type], type),
          "%s: format %s, type %s (expected %s)", name, fmt, d->type >= 1 && d->type <= 4 ? tn[d->type] : "?", type);
    CHECK(d->size[0] == sz[0] && d->size[1] == sz[1] && d->size[2] == sz[2], "%s: size %d %d %d (expected %d %d %d)", name,
          d->size[0], d->size[1], d->size[2], sz[0], sz[1], sz[2]);
    float gs[3] = {d->spacing.x, d->spacing.y, d->spacing.z}, go[3] = {d->origin.x, d->origin.y, d->origin.z};
    int geo = 1;
    for (int a = 0; a < 3; a++) geo &= fabs(gs[a] - sp[a]) <= 1e-5 * sp[a] && fabs(go[a] - org[a]) <= 1e-4 * (1 + fabs(org[a]));
    CHECK(geo, "%s: spacing %g %g %g origin %g %g %g (expected %g %g %g, %g %g %g)", name, gs[0], gs[1], gs[2], go[0], go[1],
          go[2], sp[0], sp[1], sp[2], org[0], org[1], org[2]);
    if (!strcmp(warn, "-")) CHECK(!warnings[0], "%s: no warning (%s)", name, warnings);
    else CHECK(strstr(warnings, warn) != NULL, "%s: a warning says '%s' (%s)", name, warn, warnings);
    char raw[2200];
    snprintf(raw, sizeof raw, "%s/%s.raw", dir, name);
    size_t n = 0;
    unsigned char *want = slurp(raw, &n);
    if (want) {
        size_t bytes = (size_t)sz[0] * sz[1] * sz[2] * (size_t)lci_value_size(d->type);
        size_t diff = 0, first = 0;
        for (size_t i = 0; n == bytes && i < bytes; i++)
            if (((const unsigned char *)d->data)[i] != want[i] && !diff++) first = i;
        CHECK(n == bytes && diff == 0, "%s: voxels equal the writer's (%zu of %zu bytes differ, the first at byte %zu)",
              name, diff, bytes, first);
        free(want);
    }
    lci_loaded_free(&l);
}

static void check_fail(lc_device *dev, const char *dir, char *line)
{
    char name[64], input[4096], opt[256], file[512];
    int at = 0;
    if (sscanf(line, "fail %63s %4095s %255s %511s %n", name, input, opt, file, &at) != 4) {
        CHECK(0, "expect.txt line: %s", line);
        return;
    }
    req r;
    make_req(&r, dir, input, opt);
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, r.path, &r.d, &v);
    const char *m = lc_last_error();
    char fpath[2200];
    snprintf(fpath, sizeof fpath, "%s/%s", dir, file);
    int says = 1;
    char words[1024];
    snprintf(words, sizeof words, "%s", line + at);
    words[strcspn(words, "\n")] = 0;
    for (char *w = strtok(words, "|"); w; w = strtok(NULL, "|")) /* each phrase must appear */
        if (!strstr(m, w)) says = 0;
    CHECK(s != LC_OK && !v && strstr(m, fpath) && says && !strchr(m, '\n'), "%s: fails naming %s and saying %s: %s", name,
          file, line + at, m);
    lc_volume_destroy(v);
}

int main(int argc, char **argv)
{
    if (argc < 3) return fprintf(stderr, "usage: test_dicom BUILD_DIR SOURCE_DIR\n"), 2;
    char dir[1024], cmd[4200];
    snprintf(dir, sizeof dir, "%s/dicom_cases", argv[1]);
    lc_device *dev;
    lc_device_desc dd = {.threads = 1, .log = on_log};
    if (lc_device_create(&dd, &dev) != LC_OK) return fprintf(stderr, "%s\n", lc_last_error()), 1;
    int have = 0;
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) == LC_OK && !strcmp(f.name, "dicom")) have = f.available;
    }
    CHECK(have == LC_HAVE_GDCM, "feature dicom reports %d", have);
    if (!LC_HAVE_GDCM) { /* the registry still knows DICOM files and folders, and names the package */
        mkdir(dir, 0700);
        char f[1100];
        snprintf(f, sizeof f, "%s/x.dcm", dir);
        FILE *o = fopen(f, "wb");
        unsigned char b[200] = {0};
        memcpy(b + 128, "DICM", 4);
        if (o) fwrite(b, 1, sizeof b, o), fclose(o);
        for (int k = 0; k < 2; k++) {
            const char *p = k ? dir : f;
            lc_volume *v = NULL;
            lc_status s = lc_volume_load(dev, p, NULL, &v);
            CHECK(s == (k ? LC_ERROR_IO : LC_ERROR_UNSUPPORTED) && strstr(lc_last_error(), "libgdcm-dev") &&
                      strstr(lc_last_error(), p),
                  "without GDCM %s fails naming libgdcm-dev: %s", p, lc_last_error());
        }
        lc_device_destroy(dev);
        return check_summary("dicom");
    }
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 %s/tests/dicom_write.py %s", argv[2], dir);
    int rc = system(cmd);
    if (rc == -1 || !WIFEXITED(rc) || WEXITSTATUS(rc) != 0) {
        int code = rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
        lc_device_destroy(dev);
        if (code == 77 || code == 127) {
            printf("dicom: no writer (/usr/bin/python3 with python3-pydicom and python3-numpy): skipped\n");
            return 77;
        }
        fprintf(stderr, "dicom: %s failed (%d)\n", cmd, code);
        return 1;
    }
    char ef[1100];
    snprintf(ef, sizeof ef, "%s/expect.txt", dir);
    FILE *e = fopen(ef, "r");
    CHECK(e != NULL, "%s opens", ef);
    char line[8192];
    int cases = 0;
    while (e && fgets(line, sizeof line, e)) {
        if (!strncmp(line, "ok ", 3)) check_ok(dev, dir, line), cases++;
        else if (!strncmp(line, "fail ", 5)) check_fail(dev, dir, line), cases++;
    }
    if (e) fclose(e);
    CHECK(cases >= 15, "%d cases", cases);
    /* the series listing names both series of the folder, with their sizes */
    char two[1100], about[8192];
    snprintf(two, sizeof two, "%s/two", dir);
    lc_status s = lc_file_describe(dev, two, NULL, about, sizeof about);
    CHECK(s == LC_OK && strstr(about, "series 1") && strstr(about, "series 2") && strstr(about, "MR") &&
              strstr(about, "CT") && strstr(about, "dims 9 x 10 x 7") && strstr(about, "dims 11 x 8 x 5") &&
              strstr(about, "intercept -10"),
          "lc_file_describe lists both series:\n%s", about);
    /* an enhanced file whose frames carry their own rescales says so */
    snprintf(two, sizeof two, "%s/mf_ct.dcm", dir);
    s = lc_file_describe(dev, two, NULL, about, sizeof about);
    CHECK(s == LC_OK && strstr(about, "dims 14 x 10 x 6") && strstr(about, "(varies per frame)"),
          "lc_file_describe of mf_ct.dcm: rescale varies per frame:\n%s", about);
    /* the command line: --series, several files as inputs, the listing */
    if (argc > 3) {
        char out[8192];
        struct {
            const char *args, *says;
            int rc;
        } cli[] = {
            {"info %s/two --series 2", "volume        11x8x5 float32", 0},
            {"info %s/two", "series 2  ", 1},
            {"info %s/ct/im011.dcm %s/ct/im009.dcm %s/ct/im008.dcm %s/ct/im006.dcm %s/ct/im005.dcm %s/ct/im000.dcm",
             "volume        24x20x6 int16", 0},
            {"render %s/two --series 9 -o %s/never.png --size 8x8", "series 9: the input holds series 1 to 2", 1},
            {"render %s/mf.dcm --series 1 -o %s/mf.png --size 16x16", "wrote", 0},
        };
        for (size_t c = 0; c < sizeof cli / sizeof cli[0]; c++) {
            char args[4096];
            snprintf(args, sizeof args, cli[c].args, dir, dir, dir, dir, dir, dir);
            snprintf(cmd, sizeof cmd, "%s %s 2>&1", argv[3], args);
            FILE *p = popen(cmd, "r");
            size_t n = p ? fread(out, 1, sizeof out - 1, p) : 0;
            out[n] = 0;
            int st = p ? pclose(p) : -1;
            CHECK(st != -1 && WIFEXITED(st) && WEXITSTATUS(st) == cli[c].rc && strstr(out, cli[c].says),
                  "lanecast %s: exit %d, says '%s'", args, cli[c].rc, cli[c].says);
        }
    }
    /* a folder without DICOM images is an I/O error, as any folder was before */
    char empty[1100];
    snprintf(empty, sizeof empty, "%s/empty", dir);
    mkdir(empty, 0700);
    lc_volume *ev = NULL;
    s = lc_volume_load(dev, empty, NULL, &ev);
    CHECK(s == LC_ERROR_IO && !ev && strstr(lc_last_error(), "is a directory"), "an empty folder: %s", lc_last_error());
    /* a whole load through the grid kind */
    char ct[1100];
    snprintf(ct, sizeof ct, "%s/ct", dir);
    lc_volume *v = NULL;
    lc_grid_info gi;
    s = lc_volume_load(dev, ct, NULL, &v);
    CHECK(s == LC_OK && lc_grid_get_info(v, &gi) == LC_OK && gi.size[0] == 24 && gi.size[1] == 20 && gi.size[2] == 12,
          "lc_volume_load of the CT folder makes a 24 x 20 x 12 grid (%s)", s == LC_OK ? "ok" : lc_last_error());
    lc_volume_destroy(v);
    lc_device_destroy(dev);
    return check_summary("dicom");
}
