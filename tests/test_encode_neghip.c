/* The RBF encoder on the real neghip (issue 10: "encoding neghip ... reaches
 * <= 2 % RMS"): encoded with --centre maxerr and otherwise default options,
 * the report says the target was reached at no more RBFs than the paper's
 * density allows (its 812 RBFs on 32^3 voxels is one per 40 voxels; here
 * at most one per 36 of the 66^3), the independent evaluator tests/ref
 * agrees with the reported RMS over every voxel, the first half of the set
 * fails that same check, and the error the progress reports never rises
 * as RBFs are added and polished (strictly lower at 1024 than at 256 RBFs).
 * Prints the count and the time. Args: the shared data folder.
 *
 * The same checks on neghip averaged 2x2x2 down to 33^3 (the size of the
 * paper's version). Under ASan + UBSan the whole test takes about 30 s on
 * 2 cores (docs/bench/rbf.md), so it runs at full size in every build. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lanecast/lanecast.h"
#include "ref/ref_fields.h"

#define NMAX 66
#define MAX_PROGRESS 65536

/* The progress reports: the RMS never rises; at powers of two of RBFs from
 * 16 on it falls strictly. */
typedef struct trace {
    int n, nonincreasing, falling, pow2;
    double at_pow2, last;
} trace;

static void on_progress(void *user, const lc_rbf_encode_progress *p)
{
    trace *t = user;
    if (t->n && p->rms > t->last * (1.0 + 1e-9)) t->nonincreasing = 0;
    if (!p->polish && p->rbfs >= 16 && !(p->rbfs & (p->rbfs - 1))) {
        if (t->pow2 && !(p->rms < t->at_pow2)) t->falling = 0;
        t->at_pow2 = p->rms, t->pow2++;
    }
    t->last = p->rms, t->n++;
}

static int have_lapacke(void)
{
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) == LC_OK && !strcmp(f.name, "lapacke")) return f.available;
    }
    return 0;
}

/* RMS over the n^3 nodes (unit spacing) of the first m terms of d, by the
 * reference evaluator, relative to range. */
static double ref_rms(const lc_rbf_desc *d, size_t m, const float *v, int n, double range)
{
    double *c = malloc(sizeof(double) * 3 * (m + 1)), *s = malloc(sizeof(double) * (m + 1)), *w = malloc(sizeof(double) * (m + 1));
    double wmax = 0, sse = 0;
    for (size_t i = 0; i < d->count; i++) wmax = fmax(wmax, fabs(d->weights[i]));
    for (size_t i = 0; i < m; i++) {
        for (int a = 0; a < 3; a++) c[3 * i + a] = d->centres[3 * i + a];
        s[i] = d->widths[i], w[i] = d->weights[i];
    }
    /* the truncation a loaded set uses: eps = 1e-4 max |w| of the whole set */
    ref_rbf_set set = {m, c, s, w, d->bias, wmax > 0 ? 1e-4 * wmax : 1e-30};
    for (int z = 0, j = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++, j++) {
                double p[3] = {x, y, z}, f;
                ref_rbf_eval(&set, p, &f, NULL);
                sse += (f - v[j]) * (f - v[j]);
            }
    free(c), free(s), free(w);
    return sqrt(sse / ((double)n * n * n)) / range;
}

/* neghip.raw (66^3 uint8) as floats, or averaged 2x2x2 down to 33^3. */
static int read_neghip(const char *dir, int small, float *v, int *n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/volumes/neghip.raw", dir);
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    static unsigned char raw[NMAX * NMAX * NMAX];
    size_t got = fread(raw, 1, sizeof raw, f);
    fclose(f);
    if (got != sizeof raw) return -1;
    int h = small ? 2 : 1;
    *n = NMAX / h;
    for (int z = 0, j = 0; z < *n; z++)
        for (int y = 0; y < *n; y++)
            for (int x = 0; x < *n; x++, j++) {
                double s = 0;
                for (int dz = 0; dz < h; dz++)
                    for (int dy = 0; dy < h; dy++)
                        for (int dx = 0; dx < h; dx++)
                            s += raw[((size_t)(h * z + dz) * NMAX + (size_t)(h * y + dy)) * NMAX + (size_t)(h * x + dx)];
                v[j] = (float)(s / (h * h * h));
            }
    return 0;
}

/* Encodes neghip (small: averaged down to 33^3) and checks it. */
static void encode_neghip(lc_device *dev, const char *data, int small)
{
    static float v[NMAX * NMAX * NMAX];
    int n = 0;
    if (read_neghip(data, small, v, &n)) return;
    lc_grid_desc g = {.size = {n, n, n}, .type = LC_VALUE_FLOAT32, .data = v};
    lc_samples *sm = NULL;
    CHECK(lc_samples_create(dev, &(lc_samples_desc){.grid = &g}, &sm) == LC_OK, "neghip%s as %d^3 samples",
          small ? " averaged 2x2x2" : "", n);
    size_t voxels = (size_t)n * n * n, most = voxels / 36;
    trace t = {0, 1, 1, 0, 0, 0};
    lc_rbf_encode_desc d = {.centre = LC_RBF_CENTRE_MAXERR, .max_rbfs = most, .progress = on_progress, .progress_user = &t};
    lc_rbf_encoded *set = NULL;
    lc_rbf_encode_report rep = {0};
    lc_status s = sm ? lc_rbf_encode(dev, sm, &d, &set, &rep) : LC_ERROR_INVALID_ARGUMENT;
    CHECK(s == LC_OK, "encode %s", s == LC_OK ? "" : lc_last_error());
    if (s == LC_OK) {
        printf("     neghip %d^3: %zu RBFs (one per %.0f voxels), RMS %.3f%%, max %.1f%% of the range, %.1f s\n", n,
               rep.rbfs, (double)voxels / (double)rep.rbfs, 100 * rep.rms, 100 * rep.max_error, rep.seconds);
        CHECK(rep.reached && rep.rms <= 0.02, "report: RMS %.3f%% <= 2%%, reached", 100 * rep.rms);
        CHECK(rep.rbfs == set->desc.count && rep.rbfs >= 1 && rep.rbfs <= most,
              "count %zu (the set holds %zu) <= %zu, one per 36 voxels", rep.rbfs, set->desc.count, most);
        double range = rep.range[1] - rep.range[0];
        CHECK(range > 0 && rep.fitted == voxels, "range %g..%g, %zu of %zu voxels fitted", (double)rep.range[0],
              (double)rep.range[1], rep.fitted, voxels);
        double rr = ref_rms(&set->desc, set->desc.count, v, n, range);
        CHECK(rr <= 0.02 && fabs(rr - rep.rms) < 1e-4, "reference evaluator: RMS %.4f%% <= 2%%, the report's %.4f%%",
              100 * rr, 100 * rep.rms);
        double half = ref_rms(&set->desc, set->desc.count / 2, v, n, range);
        CHECK(half > 0.02, "the check bites: the first half of the set has RMS %.3f%% > 2%%", 100 * half);
        CHECK(t.n > 0 && t.nonincreasing, "the progress RMS never rises (%d reports, last %.3f%%)", t.n, 100 * t.last);
        CHECK(t.pow2 >= 4 && t.falling, "RMS falls strictly at each of %d powers of two of RBFs from 16 on", t.pow2);
    }
    lc_rbf_encoded_free(set);
    lc_samples_destroy(sm);
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "../shared/data";
    static float probe[NMAX * NMAX * NMAX];
    int n = 0;
    if (read_neghip(data, 0, probe, &n)) {
        printf("skip: %s/volumes/neghip.raw (66^3 uint8) is not there\n", data);
        return 77;
    }
    if (!have_lapacke()) {
        printf("skip: this build has no LAPACKE (the encoder's least squares)\n");
        return 77;
    }
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    encode_neghip(dev, data, 1);
    encode_neghip(dev, data, 0);
    lc_device_destroy(dev);
    return check_summary("test_encode_neghip");
}
