/* GROMACS .gro (host/formats/gro.c): the shared water box (counts, bounds
 * against its own box line, atoms checked against the file's lines parsed
 * here independently), frames, the element rule, options, gzip with and
 * without zlib, and malformed variants that must each fail with one message
 * naming the file and the line. Args: DATA_DIR TMP_DIR. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "check.h"
#include "gzip_stored.h"
#include "host/formats/format.h"

static lc_device *dev;
static const char *tmp;
static int have_zlib;

static const char *tpath(const char *name)
{
    static char buf[8][1024];
    static int k;
    char *p = buf[k++ % 8];
    snprintf(p, sizeof buf[0], "%s/%s", tmp, name);
    return p;
}

static void put(const char *name, const char *text)
{
    FILE *f = fopen(tpath(name), "wb");
    if (f) fputs(text, f), fclose(f);
}

/* Reads path through the gro reader itself: the descriptor, or NULL (message in lc_last_error). */
static const lc_particles_desc *read_gro(const char *path, int64_t frame, const lc_option *o, int n, lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    lc_load_desc d = {.frame = frame, .options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, NULL};
    return lci_format_gro.read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

static const char six[] = "water, 2 molecules\n"
                          "    6\n"
                          "    1SOL     OW    1   0.569   1.275   1.165\n"
                          "    1SOL    HW1    2   0.476   1.268   1.128\n"
                          "    1SOL    HW2    3   0.580   1.364   1.209\n"
                          "    2SOL     OW    4   1.555   1.511   0.703  0.1234 -0.5000  0.0001\n"
                          "    2SOL    HW1    5   1.498   1.495   0.784\n"
                          "    2SOL    HW2    6   1.496   1.521   0.623\n"
                          "   2.00000   2.00000   2.00000\n";

static void frames_and_elements(void)
{
    char buf[4096];
    snprintf(buf, sizeof buf, "%s%s%s", six,
             "frame 1\n    3\n    1NA      NA    1   0.100   0.200   0.300\n"
             "    2CL      CL    2   1.000   1.000   1.000\n    3CA      CA    3   0.500   0.500   0.500\n"
             "   2.0 2.0 2.0\n",
             "frame 2, %10.5f columns\n    2\n    4ALA     CA    4   0.60000   0.60000   0.60000\n"
             "    5ALA    1HB    5   0.00012   1.00000  -1.00000\n   2.0 2.0 2.0\n");
    put("m3.gro", buf);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("m3.gro"), NULL, &fi) == LC_OK && !strcmp(fi.format, "gro") && fi.frames == 3 &&
              fi.kind == LC_KIND_PARTICLES,
          "probe: gro, particles, 3 frames (got %lld)", (long long)fi.frames);
    lci_loaded l;
    const lc_particles_desc *d = read_gro(tpath("m3.gro"), 0, NULL, 0, &l);
    CHECK(d && d->count == 6 && fabsf(d->positions[9] - 15.55f) < 1e-4f && fabsf(d->positions[11] - 7.03f) < 1e-4f &&
              fabsf(d->radii[0] - 0.66f) < 1e-6f && fabsf(d->radii[1] - 0.31f) < 1e-6f,
          "frame 0: 6 atoms, nm read as Angstrom, O and H radii (velocities ignored)");
    lci_loaded_free(&l);
    d = read_gro(tpath("m3.gro"), 1, NULL, 0, &l);
    CHECK(d && d->count == 3 && fabsf(d->radii[0] - 1.66f) < 1e-6f && fabsf(d->radii[1] - 1.02f) < 1e-6f &&
              fabsf(d->radii[2] - 1.76f) < 1e-6f,
          "frame 1: ions NA/NA -> Na, CL/CL -> Cl, CA/CA -> Ca");
    lci_loaded_free(&l);
    d = read_gro(tpath("m3.gro"), 2, NULL, 0, &l);
    CHECK(d && d->count == 2 && fabsf(d->radii[0] - 0.76f) < 1e-6f && fabsf(d->radii[1] - 0.31f) < 1e-6f &&
              fabsf(d->positions[3] - 0.0012f) < 1e-7f &&
              d->positions[4] == 10.0f && d->positions[5] == -10.0f,
          "frame 2: CA in ALA -> C, 1HB -> H, 10-wide columns found by the decimal points");
    lci_loaded_free(&l);
    d = read_gro(tpath("m3.gro"), 3, NULL, 0, &l);
    CHECK(!d && strstr(lc_last_error(), "frame 3 is past the end") && strstr(lc_last_error(), "holds 3 frames"),
          "frame 3 fails naming the frame count: %s", lc_last_error());
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, tpath("m3.gro"), &(lc_load_desc){.frame = 1}, &v) == LC_OK, "lc_volume_load frame 1");
    lc_particles_info pi;
    CHECK(v && lc_particles_get_info(v, &pi) == LC_OK && pi.count == 3, "lc_load_desc.frame reaches the reader");
    lc_volume_destroy(v);
}

static void options(void)
{
    put("six.gro", six);
    lci_loaded l;
    lc_option r[] = {{"radius", "2"}};
    const lc_particles_desc *d = read_gro(tpath("six.gro"), 0, r, 1, &l);
    CHECK(d && d->radii[0] == 2.0f && d->radii[5] == 2.0f, "radius = 2 for every atom");
    lci_loaded_free(&l);
    lc_option s[] = {{"radius_scale", "0.5"}, {"fields", "element"}};
    d = read_gro(tpath("six.gro"), 0, s, 2, &l);
    CHECK(d && fabsf(d->radii[0] - 0.33f) < 1e-6f && d->nfields == 2 && d->fields[0] == 0 && d->fields[1] == 1 &&
              d->fields[3] == 0,
          "radius_scale = 0.5, fields = element: O field 0, H field 1");
    lci_loaded_free(&l);
    lc_option bad[] = {{"fields", "bogus"}};
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, tpath("six.gro"), &(lc_load_desc){.options = bad, .noptions = 1}, &v) ==
                  LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "fields"),
          "fields = bogus fails naming the key: %s", lc_last_error());
    lc_option byres[] = {{"field_by", "residue"}};
    lc_particles_info pi = {0};
    CHECK(lc_volume_load(dev, tpath("six.gro"), &(lc_load_desc){.options = byres, .noptions = 1}, &v) == LC_OK &&
              lc_particles_get_info(v, &pi) == LC_OK && pi.nfields >= 1,
          "field_by = residue loads a .gro (%d fields by residue name)", pi.nfields);
    lc_volume_destroy(v);
    v = NULL;
    /* gzip: written without zlib (stored blocks) */
    CHECK(gzs_write(tpath("six.gro.gz"), six, strlen(six)) == 0, "write six.gro.gz");
    lc_status st = lc_volume_load(dev, tpath("six.gro.gz"), NULL, &v);
    if (have_zlib)
        CHECK(st == LC_OK && lc_particles_get_info(v, &(lc_particles_info){0}) == LC_OK, "six.gro.gz loads with zlib");
    else
        CHECK(st == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "six.gro.gz: gzip-compressed input needs zlib") &&
                  strstr(lc_last_error(), "install zlib1g-dev"),
              "six.gro.gz without zlib: %s", lc_last_error());
    lc_volume_destroy(v);
}

/* Each variant must fail with LC_ERROR_FORMAT and a message "FILE:LINE: ...". */
static void malformed(void)
{
    static const struct {
        const char *name, *text;
        int line;
        const char *says;
    } cases[] = {
        {"trunc.gro", "t\n    2\n    1SOL     OW    1   0.569   1.275   1.165\n    1SOL    HW1    2   0.476   1.2\n"
                      "   2.0 2.0 2.0\n", 4, "expected at least 44"},
        {"count_big.gro", "t\n    3\n    1SOL     OW    1   0.569   1.275   1.165\n"
                          "    1SOL    HW1    2   0.476   1.268   1.128\n   2.0 2.0 2.0\n", 5, "too large"},
        {"count_small.gro", "t\n    1\n    1SOL     OW    1   0.569   1.275   1.165\n"
                            "    1SOL    HW1    2   0.476   1.268   1.128\n   2.0 2.0 2.0\n", 4, "does the count on line 2"},
        {"bad_number.gro", "t\n    2\n    1SOL     OW    1   0.569   1.275   1.165\n"
                           "    1SOL    HW1    2   0.476   1.2x8   1.128\n   2.0 2.0 2.0\n", 4, "y coordinate '1.2x8'"},
        {"no_box.gro", "t\n    2\n    1SOL     OW    1   0.569   1.275   1.165\n"
                       "    1SOL    HW1    2   0.476   1.268   1.128\n", 5, "box line"},
        {"bad_box.gro", "t\n    1\n    1SOL     OW    1   0.569   1.275   1.165\n   2.0 2.0\n", 4, "box line"},
        {"bad_count.gro", "t\n  2a\n", 2, "atom count"},
        {"title_only.gro", "t\n", 2, "atom count"},
        {"short_file.gro", "t\n    3\n    1SOL     OW    1   0.569   1.275   1.165\n", 4, "ends after 1 of the 3 atoms"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        put(cases[i].name, cases[i].text);
        char where[1200];
        snprintf(where, sizeof where, "%s:%d: ", tpath(cases[i].name), cases[i].line);
        lc_volume *v = NULL;
        lc_status s = lc_volume_load(dev, tpath(cases[i].name), NULL, &v);
        const char *msg = lc_last_error();
        CHECK(s == LC_ERROR_FORMAT && !v && !strncmp(msg, where, strlen(where)) && strstr(msg, cases[i].says) &&
                  !strchr(msg, '\n'),
              "%s fails at line %d: %s", cases[i].name, cases[i].line, msg);
        lc_volume_destroy(v);
    }
    put("empty.gro", "");
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, tpath("empty.gro"), NULL, &v) == LC_ERROR_FORMAT && strstr(lc_last_error(), "empty file"),
          "empty.gro: %s", lc_last_error());
}

/* The water box: its lines read here with sscanf on the fixed columns. */
typedef struct gro_text {
    char **lines;
    long n;
} gro_text;

static int read_all(const char *cmd, gro_text *g)
{
    FILE *p = popen(cmd, "r");
    if (!p) return -1;
    char line[256];
    long cap = 0;
    while (fgets(line, sizeof line, p)) {
        if (g->n == cap) {
            cap = cap ? 2 * cap : 1 << 16;
            char **nl = realloc(g->lines, sizeof *nl * (size_t)cap);
            if (!nl) break;
            g->lines = nl;
        }
        g->lines[g->n++] = strdup(line);
    }
    return pclose(p) == 0 && g->n > 3 ? 0 : -1;
}

static double col(const char *line, int start, int w)
{
    char b[32];
    snprintf(b, sizeof b, "%.*s", w, line + start);
    return atof(b);
}

static int water_box(const char *data_dir)
{
    char gz[1024], cmd[1200];
    snprintf(gz, sizeof gz, "%s/particles/bigbox_water.gro.gz", data_dir);
    struct stat st;
    if (stat(gz, &st) != 0) {
        printf("skip: %s is absent (shared data: see ../shared/data/README.md or -Ddata_dir)\n", gz);
        return 77;
    }
    gro_text g = {0};
    snprintf(cmd, sizeof cmd, "gzip -dc '%s'", gz);
    if (read_all(cmd, &g) != 0) {
        printf("skip: cannot read %s through gzip -dc\n", gz);
        return 77;
    }
    long natoms = atol(g.lines[1]);
    double box[3];
    CHECK(sscanf(g.lines[g.n - 1], "%lf %lf %lf", &box[0], &box[1], &box[2]) == 3 && natoms == g.n - 3,
          "the file itself: %ld atoms, box %g %g %g nm", natoms, box[0], box[1], box[2]);
    FILE *f = fopen(tpath("bigbox_water.gro"), "wb"); /* a plain copy: the stdio path in every build */
    for (long i = 0; f && i < g.n; i++) fputs(g.lines[i], f);
    if (f) fclose(f);
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, gz, NULL, &v);
    if (have_zlib) {
        lc_particles_info pi;
        CHECK(s == LC_OK && lc_particles_get_info(v, &pi) == LC_OK && (long)pi.count == natoms &&
                  pi.min_radius == 0.31f && pi.max_radius == 0.66f,
              "bigbox_water.gro.gz: %ld atoms, O and H radii", natoms);
        int inside = 1, spans = 1;
        for (int a = 0; a < 3 && s == LC_OK; a++) {
            float lo = (&pi.bounds.lo.x)[a], hi = (&pi.bounds.hi.x)[a], b = (float)(10.0 * box[a]);
            inside &= lo >= -1.0f && hi <= b + 1.0f; /* a water's H may stick 1 A out of the box */
            spans &= hi - lo > 0.98f * b;
        }
        CHECK(inside && spans, "centres fill the box line's %g x %g x %g A (within 1 A)", 10 * box[0], 10 * box[1],
              10 * box[2]);
    } else {
        CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "gzip-compressed input needs zlib"),
              "bigbox_water.gro.gz without zlib: %s", lc_last_error());
    }
    lc_volume_destroy(v);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, gz, NULL, &fi) == LC_OK && fi.kind == LC_KIND_PARTICLES && fi.gzip == 1 &&
              fi.frames == (have_zlib ? 1 : 0),
          "probe: gro, gzip, frames %lld", (long long)fi.frames);
    lci_loaded l;
    const lc_particles_desc *d = read_gro(tpath("bigbox_water.gro"), 0, NULL, 0, &l);
    CHECK(d && (long)d->count == natoms, "plain copy: %ld atoms", natoms);
    long spot[] = {0, 1, 70001, natoms / 2, natoms - 1};
    for (size_t k = 0; d && k < sizeof spot / sizeof spot[0]; k++) {
        const char *line = g.lines[spot[k] + 2];
        int bad = 0;
        for (int c = 0; c < 3; c++) bad |= fabs(d->positions[3 * spot[k] + c] - 10.0 * col(line, 20 + 8 * c, 8)) > 1e-4;
        float r = strstr(line, " OW ") ? 0.66f : 0.31f;
        CHECK(!bad && d->radii[spot[k]] == r, "atom %ld = line %ld '%.44s' x10, radius %.2f", spot[k], spot[k] + 3, line,
              (double)r);
    }
    lci_loaded_free(&l);
    for (long i = 0; i < g.n; i++) free(g.lines[i]);
    free(g.lines);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_gro DATA_DIR TMP_DIR\n");
        return 2;
    }
    tmp = argv[2];
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info fi;
        if (lc_feature_get(i, &fi) == LC_OK && !strcmp(fi.name, "zlib")) have_zlib = fi.available;
    }
    CHECK(have_zlib == LC_HAVE_ZLIB, "lc_feature_get(zlib) = %d agrees with LC_HAVE_ZLIB", have_zlib);
    if (lc_device_create(&(lc_device_desc){.threads = 2}, &dev) != LC_OK) return 1;
    frames_and_elements();
    options();
    malformed();
    int data = water_box(argv[1]);
    lc_device_destroy(dev);
    int rc = check_summary("test_gro");
    return rc ? rc : data;
}
