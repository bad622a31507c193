/* `value = NAME` takes any per-particle block of an SPH snapshot (issue 27),
 * against files this test writes with known values:
 * (a) GADGET format 2: a block by its label (TEMP, gas only), a component
 *     (VEL:1) and the magnitude (|VEL|) of a 3-per-particle block over all
 *     types, the u alias; errors naming the file and the missing label, a
 *     3-vector without a component, a component of a scalar block, the ID
 *     block, a block matching no particle count;
 * (b) GADGET format 1: the standard blocks by position (NE with cooling on);
 * (c) HDF5: any dataset of the PartTypeN groups by name (Temperature,
 *     ElementAbundance/Oxygen as N x 1, Velocities:2 and |Velocities| of
 *     N x 3); errors naming the file, the group and the dataset (missing,
 *     misshapen, no component given, a component out of range);
 * (d) SPH weights with a named value: k = m / rho * A, and with normalise = 1
 *     the norm_weights m / rho, both formats;
 * (e) lc_file_describe (lanecast info) lists the blocks and the datasets. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "tmpfiles.h"
#include "host/formats/format.h"
#if LC_HAVE_HDF5
#include <hdf5.h>
#endif

static lc_device *dev;

static const lc_particles_desc *read_with(const lci_format *fmt, const char *path, const lc_option *o, int n,
                                          lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    lc_load_desc d = {.options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, fmt->name};
    return fmt->read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

#define LOAD(...) (&(lc_load_desc){.options = (lc_option[]){__VA_ARGS__}, .noptions = sizeof((lc_option[]){__VA_ARGS__}) / sizeof(lc_option)})
#define OPTS(...) (lc_option[]){__VA_ARGS__}, (int)(sizeof((lc_option[]){__VA_ARGS__}) / sizeof(lc_option))

/* 3 gas particles (type 0) and 2 of type 1; the known values per particle */
enum { NG = 3, ND = 2, NT = NG + ND };
static float pos[3 * NT], vel[3 * NT], mass[NG], u[NG], rho[NG], hsml[NG], temp[NG], ne[NG];
static const double mtab1 = 0.25; /* type 1's mass-table entry */

static void make_values(void)
{
    for (int i = 0; i < NT; i++)
        for (int a = 0; a < 3; a++) pos[3 * i + a] = (float)(i + 0.1 * a), vel[3 * i + a] = (float)(i + 1) * (a + 1.0f);
    for (int i = 0; i < NG; i++) {
        mass[i] = 1.0f + (float)i, u[i] = 10.0f + (float)i, rho[i] = 0.5f * (float)(i + 1), hsml[i] = 0.7f + 0.1f * (float)i;
        temp[i] = 100.0f * (float)(i + 1), ne[i] = 0.01f * (float)(i + 1);
    }
}

static void rec(FILE *f, const void *p, int32_t n)
{
    fwrite(&n, 4, 1, f);
    fwrite(p, 1, (size_t)n, f);
    fwrite(&n, 4, 1, f);
}

static void label(FILE *f, const char *name, int32_t n)
{
    char b[8];
    memcpy(b, name, 4);
    int32_t s = n + 8;
    memcpy(b + 4, &s, 4);
    rec(f, b, 8);
}

/* format 2 (labels) or 1 (positions; cooling on: NE, NH after RHO) */
static void write_gadget(const char *name, int format)
{
    FILE *f = fopen(tpath(name), "wb");
    if (!f) return;
    unsigned char h[256] = {0};
    int32_t np[6] = {NG, ND, 0, 0, 0, 0}, one = 1;
    double mt[6] = {0, mtab1, 0, 0, 0, 0};
    memcpy(h, np, sizeof np);
    memcpy(h + 24, mt, sizeof mt);
    memcpy(h + 96, np, sizeof np);
    if (format == 1) memcpy(h + 120, &one, 4); /* flag_cooling */
    memcpy(h + 124, &one, 4);
    uint32_t ids[NT] = {1, 2, 3, 4, 5};
    struct {
        const char *name;
        const void *p;
        int32_t n;
    } b[] = {{"HEAD", h, 256},          {"POS ", pos, 12 * NT},  {"VEL ", vel, 12 * NT},   {"ID  ", ids, 4 * NT},
             {"MASS", mass, 4 * NG},    {"U   ", u, 4 * NG},     {"RHO ", rho, 4 * NG},    {"NE  ", ne, 4 * NG},
             {"NH  ", ne, 4 * NG},      {"HSML", hsml, 4 * NG},  {"TEMP", temp, 4 * NG},   {"JUNK", temp, 8}};
    for (size_t i = 0; i < sizeof b / sizeof b[0]; i++) {
        if (format == 1 && i >= 10) break; /* format 1: the standard blocks only */
        if (format == 2 && (i == 7 || i == 8)) continue; /* no cooling blocks in the labelled file */
        if (format == 2) label(f, b[i].name, b[i].n);
        rec(f, b[i].p, b[i].n);
    }
    fclose(f);
}

static int values_are(const lc_particles_desc *d, size_t n, const float *want, float tol)
{
    if (!d || !d->values || d->count != n) return 0;
    for (size_t i = 0; i < n; i++)
        if (!(fabsf(d->values[i] - want[i]) <= tol * fabsf(want[i]))) return 0;
    return 1;
}

static void must_fail(const char *path, const char *says, const char *says2, lc_status want, const lc_load_desc *d)
{
    load_must_fail(dev, path, ": ", says, says2, want, d);
}

/* NAME:comp and |NAME| of the velocities of the first n particles read through fmt. */
static void check_vector(const lci_format *fmt, const char *path, const char *name, int n, int comp)
{
    float vc[NT], vm[NT];
    for (int i = 0; i < n; i++) {
        const float *v = vel + 3 * i;
        vc[i] = v[comp], vm[i] = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    char opt[2][64];
    snprintf(opt[0], sizeof opt[0], "%s:%d", name, comp);
    snprintf(opt[1], sizeof opt[1], "|%s|", name);
    for (int k = 0; k < 2; k++) {
        lci_loaded l;
        const lc_particles_desc *d = read_with(fmt, path, OPTS({"value", opt[k]}, {"radius", "1"}), &l);
        CHECK(values_are(d, (size_t)n, k ? vm : vc, k ? 1e-6f : 0.0f), "%s value = %s: %s of %d particles", path,
              opt[k], k ? "the speeds" : "the component", n);
        lci_loaded_free(&l);
    }
}

/* value = the temperatures with kernel m4 and normalise 1: k = m / rho * T, norm_weights = m / rho. */
static void check_weights(const lci_format *fmt, const char *path, const char *value)
{
    float k[NG], w[NG];
    for (int i = 0; i < NG; i++) w[i] = (float)((double)mass[i] / rho[i]), k[i] = (float)((double)w[i] * temp[i]);
    lci_loaded l;
    const lc_particles_desc *d = read_with(fmt, path, OPTS({"value", value}, {"kernel", "m4"}, {"normalise", "1"}), &l);
    int ok = values_are(d, NG, k, 1e-6f) && d->norm_weights;
    for (int i = 0; ok && i < NG; i++) ok = fabsf(d->norm_weights[i] - w[i]) <= 1e-6f * w[i];
    CHECK(ok, "%s value = %s, kernel m4, normalise 1: k = m / rho * %s, norm_weights = m / rho", path, value, value);
    lci_loaded_free(&l);
}

static void gadget(void)
{
    write_gadget("b2.g2", 2);
    write_gadget("b1.gadget", 1);
    lci_loaded l;
    const char *p2 = tpath("b2.g2");
    const lc_particles_desc *d = read_with(&lci_format_gadget, p2, OPTS({"value", "TEMP"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, temp, 0.0f), "b2.g2 value = TEMP: the gas's TEMP block (%zu particles)", d ? d->count : 0);
    lci_loaded_free(&l);
    check_vector(&lci_format_gadget, p2, "VEL", NT, 1);
    d = read_with(&lci_format_gadget, p2, OPTS({"value", "u"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, u, 0.0f), "b2.g2 value = u: the alias of U");
    lci_loaded_free(&l);
    must_fail(p2, "value = ZZZ, but the snapshot has no ZZZ  block", "lanecast info", LC_ERROR_FORMAT,
              LOAD({"value", "ZZZ"}));
    must_fail(p2, "value = VEL: block VEL  holds 3 values per particle", "|NAME|", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "VEL"}));
    must_fail(p2, "value = VEL:3", "3 values per particle", LC_ERROR_INVALID_ARGUMENT, LOAD({"value", "VEL:3"}));
    must_fail(p2, "value = TEMP:0: block TEMP holds 1 value per particle", NULL, LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "TEMP:0"}));
    must_fail(p2, "integer particle ids", NULL, LC_ERROR_INVALID_ARGUMENT, LOAD({"value", "ID"}));
    must_fail(p2, "value = JUNK: block JUNK holds 8 bytes", "neither", LC_ERROR_FORMAT, LOAD({"value", "JUNK"}));
    must_fail(p2, "value = 'TOOLONG'", "1-4 characters", LC_ERROR_INVALID_ARGUMENT, LOAD({"value", "TOOLONG"}));
    must_fail(p2, "value = TEMP is a gas quantity", "types = 0", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "TEMP"}, {"types", "0,1"}));
    /* format 1: by position */
    const char *p1 = tpath("b1.gadget");
    d = read_with(&lci_format_gadget, p1, OPTS({"value", "NE"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, ne, 0.0f), "b1.gadget (format 1, cooling) value = NE: the 8th block by position");
    lci_loaded_free(&l);
    d = read_with(&lci_format_gadget, p1, OPTS({"value", "hsml"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, hsml, 0.0f), "b1.gadget value = hsml after NE and NH");
    lci_loaded_free(&l);
    check_weights(&lci_format_gadget, p2, "TEMP"); /* SPH and normalisation weights with a named value */
    d = read_with(&lci_format_gadget, p2, OPTS({"value", "TEMP"}, {"kernel", "m4"}), &l);
    CHECK(d && !d->norm_weights, "b2.g2 without normalise: no norm_weights");
    lci_loaded_free(&l);
    must_fail(p2, "normalise = 1 is the normalised SPH interpolant", "value = A", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"kernel", "m4"}, {"normalise", "1"}));
    /* the volume renders the normalised interpolant: through lc_volume_load */
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, p2, LOAD({"value", "TEMP"}, {"kernel", "m4"}, {"normalise", "1"}), &v) == LC_OK,
          "lc_volume_load b2.g2 normalise: %s", v ? "" : lc_last_error());
    if (v) { /* at a particle's centre far from the others the field is its own A */
        float x[3] = {pos[6], pos[7], pos[8]}, val = 0.0f;
        lc_particles_info pi;
        lc_particles_get_info(v, &pi);
        CHECK(pi.params.normalise == 1 && lc_volume_sample(dev, v, 1, x, &val, NULL) == LC_OK &&
                  fabsf(val - temp[2]) < 1e-4f * temp[2],
              "normalised TEMP at gas particle 2 (H %.2f, neighbours 1 away): %g, its own %g", (double)hsml[2],
              (double)val, (double)temp[2]);
    }
    lc_volume_destroy(v);
    char text[4096];
    CHECK(lc_file_describe(dev, p2, NULL, text, sizeof text) == LC_OK && strstr(text, "TEMP (gas x 1)") &&
              strstr(text, "VEL (all x 3)") && strstr(text, "JUNK (size unmatched)"),
          "lanecast info b2.g2 lists the blocks: %s", text);
}

#if LC_HAVE_HDF5
static void h5put(hid_t g, const char *name, int rank, hsize_t n, hsize_t c, const float *v)
{
    hsize_t dims[2] = {n, c};
    hid_t sp = H5Screate_simple(rank, dims, NULL);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(lcpl, 1);
    hid_t ds = H5Dcreate2(g, name, H5T_IEEE_F32LE, sp, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
    H5Dclose(ds);
    H5Pclose(lcpl);
    H5Sclose(sp);
}
#endif

static void hdf5(void)
{
#if LC_HAVE_HDF5
    const char *path = tpath("blocks.hdf5");
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    hid_t g0 = H5Gcreate2(f, "PartType0", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    h5put(g0, "Coordinates", 2, NG, 3, pos);
    h5put(g0, "Velocities", 2, NG, 3, vel);
    h5put(g0, "Masses", 1, NG, 1, mass);
    h5put(g0, "Density", 1, NG, 1, rho);
    h5put(g0, "SmoothingLength", 1, NG, 1, hsml);
    h5put(g0, "Temperature", 1, NG, 1, temp);
    h5put(g0, "ElementAbundance/Oxygen", 2, NG, 1, ne);
    h5put(g0, "Short", 1, NG - 1, 1, temp);
    H5Gclose(g0);
    hid_t g1 = H5Gcreate2(f, "PartType1", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    h5put(g1, "Coordinates", 2, ND, 3, pos + 3 * NG);
    H5Gclose(g1);
    H5Fclose(f);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_hdf5, path, OPTS({"value", "Temperature"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, temp, 0.0f), "blocks.hdf5 value = Temperature (PartType1 skipped: it has none)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, path, OPTS({"value", "ElementAbundance/Oxygen"}, {"radius", "1"}), &l);
    CHECK(values_are(d, NG, ne, 0.0f), "blocks.hdf5 value = ElementAbundance/Oxygen (N x 1 in a subgroup)");
    lci_loaded_free(&l);
    check_vector(&lci_format_hdf5, path, "Velocities", NG, 2);
    check_weights(&lci_format_hdf5, path, "Temperature");
    must_fail(path, "/PartType0: value = Metals, but the group has no Metals dataset", "lanecast info",
              LC_ERROR_FORMAT, LOAD({"value", "Metals"}, {"types", "0"}));
    must_fail(path, "/PartType0/Velocities", "name a component Velocities:0..2 or the magnitude |Velocities|",
              LC_ERROR_INVALID_ARGUMENT, LOAD({"value", "Velocities"}));
    must_fail(path, "/PartType0/Velocities", "component 3 of 3 x 3", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "Velocities:3"}));
    must_fail(path, "/PartType0/Temperature", "no components", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "Temperature:0"}));
    must_fail(path, "/PartType0/Short", "expected 3 rows", LC_ERROR_FORMAT, LOAD({"value", "Short"}));
    must_fail(path, "option value = '|Velocities'", NULL, LC_ERROR_INVALID_ARGUMENT, LOAD({"value", "|Velocities"}));
    char text[4096];
    CHECK(lc_file_describe(dev, path, NULL, text, sizeof text) == LC_OK &&
              strstr(text, "ElementAbundance/Oxygen (3 x 1)") && strstr(text, "Velocities (3 x 3)") &&
              strstr(text, "PartType1"),
          "lanecast info blocks.hdf5 lists the datasets: %s", text);
#else
    printf("skip hdf5: built without libhdf5\n");
#endif
}

int main(int argc, char **argv)
{
    tmp = argc > 1 ? argv[1] : ".";
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    make_values();
    gadget();
    hdf5();
    lc_device_destroy(dev);
    return check_summary("sph_blocks");
}
