/* Bad input to the particle API (issue 3, Tests): lc_particles_create rejects
 * invalid particles with LC_ERROR_INVALID_ARGUMENT and a message naming the
 * first bad index and the count of bad ones, drop_invalid drops and counts;
 * lc_volume_load of particle files (xyz, pdb, raw-particles) on malformed
 * files names the file (and the line); unknown or bad options name the key.
 * usage: test_particles_input TMPDIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"

static lc_device *dev;

/* The call fails with `want` and the message contains every needle (NULL-terminated). */
static void expect(lc_status got, lc_status want, const char *what, const char *const *needles)
{
    const char *m = lc_last_error();
    int ok = got == want && !strchr(m, '\n'); /* one line: the CLI prints it as is */
    for (int i = 0; needles[i]; i++) ok = ok && strstr(m, needles[i]);
    CHECK(ok, "%-44s -> %s: \"%s\"", what, lc_status_string(got), m);
}
#define EXPECT(call, want, what, ...) expect((call), (want), (what), (const char *const[]){__VA_ARGS__, NULL})

static void create_errors(void)
{
    enum { N = 10 };
    float xyz[3 * N], r[N], k[N];
    uint8_t f[N];
    for (int i = 0; i < N; i++) xyz[3 * i] = (float)i, xyz[3 * i + 1] = 0, xyz[3 * i + 2] = 0, r[i] = 0.5f, k[i] = 1, f[i] = (uint8_t)(i % 2);
    lc_volume *p = (lc_volume *)(uintptr_t)1;
    lc_particles_desc d = {.count = N, .positions = xyz, .radii = r, .values = k, .fields = f};
    /* a NaN position at 3 and an inf one at 7: first index 3, 2 bad */
    xyz[3 * 3 + 1] = NAN, xyz[3 * 7 + 2] = INFINITY;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "NaN/inf positions at 3, 7", "particle 3", "2 of 10");
    CHECK(p == NULL, "out is NULL after a failure");
    d.drop_invalid = 1;
    lc_status s = lc_particles_create(dev, &d, &p);
    lc_particles_info info = {0};
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 8 && info.dropped == 2, "drop_invalid: kept %zu, dropped %zu", info.count, info.dropped);
    lc_volume_destroy(p);
    d.drop_invalid = 0;
    xyz[3 * 3 + 1] = 0, xyz[3 * 7 + 2] = 0;
    /* radii: zero at 2, negative at 5, inf at 6, NaN at 9 */
    r[2] = 0.0f, r[5] = -1.0f, r[6] = INFINITY, r[9] = NAN;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "radii 0, -1, inf, NaN at 2, 5, 6, 9", "particle 2", "4 of 10");
    d.drop_invalid = 1;
    s = lc_particles_create(dev, &d, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 6 && info.dropped == 4, "drop_invalid radii: kept %zu, dropped %zu", info.count, info.dropped);
    lc_volume_destroy(p);
    d.drop_invalid = 0;
    for (int i = 0; i < N; i++) r[i] = 0.5f;
    /* coordinates near float's limit (finite, so drop_invalid would keep them before) used to abort
       inside Embree's binning; they are refused, and particles 2e18 apart still build and render */
    xyz[3 * 4] = 1.7e38f, xyz[3 * 8 + 1] = -3e38f;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "coordinates 1.7e38, -3e38 at 4, 8", "particle 4",
           "2 of 10", "1e18");
    xyz[3 * 4] = 1e18f, xyz[3 * 8 + 1] = -1e18f;
    s = lc_particles_create(dev, &d, &p);
    float img[4 * 8 * 8];
    lc_status rs = s == LC_OK ? lc_render(dev, &(lc_render_desc){.width = 8, .height = 8, .volume = p}, img, NULL) : s;
    CHECK(s == LC_OK && rs == LC_OK, "particles 2e18 apart build and render: %s", lc_status_string(rs));
    lc_volume_destroy(p);
    xyz[3 * 4] = 4.0f, xyz[3 * 8 + 1] = 0.0f;
    /* one shared radius that is bad: every particle is bad */
    d.radii = NULL, d.radius = 0.0f;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "shared radius 0", "particle 0", "10 of 10");
    d.radii = r;
    /* non-finite value */
    k[4] = NAN;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "NaN value at 4", "particle 4", "1 of 10");
    k[4] = 1;
    /* field ids: 2 and 3 with nfields = 2 */
    f[6] = 2, f[8] = 3;
    d.nfields = 2;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "field ids 2, 3 with nfields 2", "particle 6", "2 of 10");
    d.nfields = 0;
    f[6] = 9, f[8] = 200;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "field ids 9, 200 (auto nfields)", "particle 6", "2 particles");
    f[6] = 0, f[8] = 0;
    d.nfields = 9;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "nfields 9", "nfields = 9");
    d.nfields = -1;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "nfields -1", "nfields = -1");
    d.nfields = 0;
    d.leaf_size = 33;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "leaf_size 33", "leaf_size = 33");
    d.leaf_size = -1;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "leaf_size -1", "leaf_size = -1");
    /* leaf_size 0 means the default 4 */
    d.leaf_size = 0;
    s = lc_particles_create(dev, &d, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.leaf_size == 4, "leaf_size 0 = default %d", info.leaf_size);
    lc_volume_destroy(p);
    d.positions = NULL;
    EXPECT(lc_particles_create(dev, &d, &p), LC_ERROR_INVALID_ARGUMENT, "NULL positions, count 10", "positions is NULL");
    d.count = 0;
    s = lc_particles_create(dev, &d, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 0, "count 0 with NULL positions is an empty scene");
    lc_volume_destroy(p);
    EXPECT(lc_particles_create(dev, NULL, &p), LC_ERROR_INVALID_ARGUMENT, "NULL desc", "desc is NULL");
    EXPECT(lc_particles_create(dev, &d, NULL), LC_ERROR_INVALID_ARGUMENT, "NULL out", "out is NULL");
    EXPECT(lc_particles_create(NULL, &d, &p), LC_ERROR_INVALID_ARGUMENT, "NULL device", "device is NULL");
    /* all invalid with drop_invalid: an empty scene */
    d = (lc_particles_desc){.count = 3, .positions = xyz, .radius = -1.0f, .drop_invalid = 1};
    s = lc_particles_create(dev, &d, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 0 && info.dropped == 3, "all dropped: kept %zu, dropped %zu", info.count, info.dropped);
    lc_volume_destroy(p);
}

static char tmpdir[512];

static const char *write_file(const char *name, const void *data, size_t n)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", tmpdir, name);
    FILE *fp = fopen(path, "wb");
    if (fp) {
        fwrite(data, 1, n, fp);
        fclose(fp);
    }
    return path;
}
#define WRITE_TEXT(name, text) write_file(name, text, strlen(text))

/* lc_volume_load with a format name (NULL = detect) and text options. */
static lc_status load(const char *path, const char *format, const lc_option *opts, int nopts, lc_volume **out)
{
    lc_load_desc d = {.format = format, .options = opts, .noptions = nopts};
    return lc_volume_load(dev, path, &d, out);
}
#define OPTS(...) (const lc_option[]){__VA_ARGS__}, (int)(sizeof((const lc_option[]){__VA_ARGS__}) / sizeof(lc_option))

static void load_errors(void)
{
    lc_volume *p = NULL;
    const char *f;
    f = WRITE_TEXT("bad_number.xyz", "3\ncomment\nC 0 0 0\nO 1.0 2.x 3\nN 1 1 1\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_FORMAT, "XYZ with a bad number on line 4", f, ":4:");
    CHECK(p == NULL, "out is NULL after a failed load");
    f = WRITE_TEXT("short_line.xyz", "C 0 0 0\nC 1 2\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_FORMAT, "XYZ with two coordinates on line 2", f, ":2:");
    f = WRITE_TEXT("short_count.xyz", "5\ncomment\nC 0 0 0\nC 1 1 1\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_FORMAT, "XYZ header count 5, 2 atoms", f, "5");
    f = WRITE_TEXT("bad.pdb",
                   "HEADER    TEST\n"
                   "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\n"
                   "ATOM      2  CA  ALA A   1      11.639   6.0x1  -5.147  1.00  0.00           C\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_FORMAT, "PDB with a bad number on line 3", f, ":3:");
    f = WRITE_TEXT("empty.pdb", "HEADER    NOTHING\nEND\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_FORMAT, "PDB without atoms", f, "no ATOM");
    /* raw data has no magic: its format is named */
    float raw[3 * 4] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3};
    f = write_file("trunc.raw", raw, sizeof raw - 5); /* 43 bytes */
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0.5"}), &p), LC_ERROR_FORMAT,
           "raw file truncated (43 of 48 bytes)", f, "43 bytes");
    f = write_file("four.raw", raw, sizeof raw);
    EXPECT(load(f, "raw-particles", OPTS({"count", "3"}, {"radius", "0.5"}), &p), LC_ERROR_FORMAT,
           "raw count 3 for 4 particles", f, "count");
    EXPECT(load(f, "raw-particles", OPTS({"count", "5"}, {"radius", "0.5"}), &p), LC_ERROR_FORMAT,
           "raw count 5 for 4 particles", f, "48 bytes");
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}), &p), LC_ERROR_INVALID_ARGUMENT, "raw without a radius", f,
           "radius");
    EXPECT(load(f, "raw-particles", OPTS({"radius", "0.5"}), &p), LC_ERROR_INVALID_ARGUMENT, "raw without a count", f,
           "count");
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0"}), &p), LC_ERROR_INVALID_ARGUMENT,
           "raw with radius 0", f, "radius", "'0'");
    EXPECT(load(f, "raw-particles", OPTS({"count", "four"}, {"radius", "0.5"}), &p), LC_ERROR_INVALID_ARGUMENT,
           "raw with count 'four'", f, "count", "four");
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0.5"}, {"colour", "red"}), &p),
           LC_ERROR_INVALID_ARGUMENT, "unknown option key 'colour'", f, "'colour'");
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0.5"}, {"brick", "4"}), &p),
           LC_ERROR_INVALID_ARGUMENT, "a grid key (brick) on particles", f, "'brick'");
    EXPECT(load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0.5"}, {"leaf_size", "33"}), &p),
           LC_ERROR_INVALID_ARGUMENT, "leaf_size 33", f, "leaf_size");
    CHECK(p == NULL, "out is NULL after a failed load with options");
    lc_status s = load(f, "raw-particles", OPTS({"count", "4"}, {"radius", "0.5"}, {"leaf_size", "2"}), &p);
    lc_particles_info info = {0};
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 4 && info.leaf_size == 2 && info.min_radius == 0.5f && info.max_radius == 0.5f,
          "raw file of 4 particles loads (%zu, leaf size %d, radius %g): %s", info.count, info.leaf_size,
          (double)info.max_radius, s == LC_OK ? "" : lc_last_error());
    lc_volume_destroy(p);
    p = NULL;
    f = WRITE_TEXT("atoms.foo", "C 0 0 0\n");
    EXPECT(load(f, NULL, NULL, 0, &p), LC_ERROR_UNSUPPORTED, "unknown extension .foo", f, "unknown file format");
    EXPECT(load(f, "gromacs", NULL, 0, &p), LC_ERROR_INVALID_ARGUMENT, "unknown format name", f, "'gromacs'");
    s = load(f, "xyz", NULL, 0, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 1, "format named xyz reads atoms.foo (%zu atoms)", info.count);
    lc_volume_destroy(p);
    p = NULL;
    char missing[1024];
    snprintf(missing, sizeof missing, "%s/does_not_exist.xyz", tmpdir);
    EXPECT(load(missing, NULL, NULL, 0, &p), LC_ERROR_IO, "missing file", missing, "cannot open");
    f = WRITE_TEXT("nan.xyz", "C 0 0 0\nC nan 1 1\nC 2 2 2\n");
    s = load(f, NULL, NULL, 0, &p);
    const char *m = lc_last_error();
    CHECK(s != LC_OK && p == NULL && strstr(m, "nan.xyz") && (strstr(m, ":2") || strstr(m, "particle 1")),
          "XYZ with a NaN coordinate on line 2 -> %s: \"%s\"", lc_status_string(s), m);
    s = load(f, NULL, OPTS({"drop_invalid", "1"}), &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.count == 2 && info.dropped == 1, "XYZ NaN with drop_invalid: kept %zu, dropped %zu",
          info.count, info.dropped);
    lc_volume_destroy(p);
    p = NULL;
    EXPECT(load(f, NULL, OPTS({"drop_invalid", "yes"}), &p), LC_ERROR_INVALID_ARGUMENT, "drop_invalid = yes", f,
           "drop_invalid", "yes");
    /* element radii, radius, radius_scale and fields = element */
    f = WRITE_TEXT("mol.xyz", "C 0 0 0\nO 1 0 0\nC 2 0 0\nH 3 0 0\n");
    s = load(f, NULL, NULL, 0, &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.nfields == 1 && info.min_radius == 0.31f && info.max_radius == 0.76f,
          "XYZ element radii H..C: %g..%g, %d field(s)", (double)info.min_radius, (double)info.max_radius, info.nfields);
    lc_volume_destroy(p);
    p = NULL;
    s = load(f, NULL, OPTS({"radius_scale", "2"}), &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.min_radius == 0.62f && info.max_radius == 1.52f, "radius_scale 2: %g..%g",
          (double)info.min_radius, (double)info.max_radius);
    lc_volume_destroy(p);
    p = NULL;
    s = load(f, NULL, OPTS({"radius", "0.7"}, {"fields", "element"}), &p);
    if (s == LC_OK) lc_particles_get_info(p, &info);
    CHECK(s == LC_OK && info.min_radius == 0.7f && info.max_radius == 0.7f && info.nfields == 3,
          "radius 0.7, fields = element: %g..%g, %d fields (C, O, H)", (double)info.min_radius,
          (double)info.max_radius, info.nfields);
    lc_volume_destroy(p);
    p = NULL;
    EXPECT(load(f, NULL, OPTS({"fields", "atoms"}), &p), LC_ERROR_INVALID_ARGUMENT, "fields = atoms", f, "fields",
           "atoms");
    EXPECT(load(f, NULL, OPTS({"count", "4"}), &p), LC_ERROR_INVALID_ARGUMENT, "count (a raw key) on xyz", f, "'count'");
    lc_file_info fi = {0};
    s = lc_file_probe(dev, f, NULL, &fi);
    CHECK(s == LC_OK && fi.format && !strcmp(fi.format, "xyz") && fi.kind == LC_KIND_PARTICLES && fi.frames == 1 &&
              fi.gzip == 0,
          "lc_file_probe mol.xyz: %s, kind %d", fi.format ? fi.format : "(null)", (int)fi.kind);
    /* a frame past a one-frame file, or a companion a format does not take, is refused */
    s = lc_volume_load(dev, f, &(lc_load_desc){.frame = 5}, &p);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && !p && strstr(lc_last_error(), "frame 5"), "frame 5 of mol.xyz: %s",
          lc_last_error());
    s = lc_volume_load(dev, f, &(lc_load_desc){.companion = "top.psf"}, &p);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && !p && strstr(lc_last_error(), "top.psf"), "companion on xyz: %s",
          lc_last_error());
}

int main(int argc, char **argv)
{
    snprintf(tmpdir, sizeof tmpdir, "%s/particles_input_XXXXXX", argc > 1 ? argv[1] : ".");
    if (!mkdtemp(tmpdir)) {
        printf("cannot create a temporary folder %s\n", tmpdir);
        return 1;
    }
    lc_device_desc dd = {.threads = 1};
    if (lc_device_create(&dd, &dev) != LC_OK) {
        printf("lc_device_create: %s\n", lc_last_error());
        return 1;
    }
    create_errors();
    load_errors();
    lc_device_destroy(dev);
    static const char *const names[] = {"bad_number.xyz", "short_line.xyz", "short_count.xyz", "bad.pdb", "empty.pdb",
                                        "trunc.raw", "four.raw", "atoms.foo", "nan.xyz", "mol.xyz"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", tmpdir, names[i]);
        remove(path);
    }
    rmdir(tmpdir);
    return check_summary("test_particles_input");
}
