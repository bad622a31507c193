/* RBF set benchmark (docs/bench/rbf.md): the BVH gather against the
 * adaptive octree of Jang 2004 §5 (lc_rbf_desc.accel) on synthetic sets,
 * fixed seeds: n RBFs uniform in [-1, 1]^3 or in 8 clusters (normal, sigma
 * 0.12), widths s = 0.5 n^(-1/3) U(0.5, 1.5) (so each point lies in a few
 * supports in the uniform sets, and in many inside clusters), weights
 * U(-0.5, 1), eps the default. Per case one machine-readable line: build
 * seconds and bytes of the structure, the median frames per second of the
 * repeats with min and max, the Gaussians per frame. Renders at the device's
 * target and threads (LANECAST_TARGET / LANECAST_THREADS), heat TF, default
 * range and step, alpha_stop 0.97, perspective view of the whole set. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"

static uint64_t rng;
static double urand(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}
static double nrand(void) { return sqrt(-2.0 * log(1.0 - urand())) * cos(6.283185307179586 * urand()); }

typedef struct set {
    size_t n;
    float *c, *s, *w;
} set;

static int make_set(set *st, size_t n, int clustered, uint64_t seed)
{
    st->n = n;
    st->c = malloc(sizeof(float) * 3 * n), st->s = malloc(sizeof(float) * n), st->w = malloc(sizeof(float) * n);
    if (!st->c || !st->s || !st->w) return -1;
    rng = seed;
    double cc[8][3];
    for (int k = 0; k < 8; k++)
        for (int a = 0; a < 3; a++) cc[k][a] = -0.7 + 1.4 * urand();
    double s0 = 0.5 * pow((double)n, -1.0 / 3.0);
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            double x = clustered ? cc[i % 8][a] + 0.12 * nrand() : -1.0 + 2.0 * urand();
            st->c[3 * i + a] = (float)fmin(fmax(x, -1.0), 1.0);
        }
        st->s[i] = (float)(s0 * (0.5 + urand()));
        st->w[i] = (float)(-0.5 + 1.5 * urand());
    }
    return 0;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* One case: builds the set with the accel, renders `repeats` frames after a warm-up. */
static int run_case(lc_device *dev, const set *st, const char *layout, lc_rbf_accel accel, int cell_max, int size,
                    int repeats)
{
    lc_rbf_desc d = {.count = st->n, .centres = st->c, .widths = st->s, .weights = st->w, .accel = accel,
                     .cell_max = cell_max};
    lc_volume *v = NULL;
    lc_rbf_info in;
    lc_tf *tf = NULL;
    if (lc_rbf_create(dev, &d, &v) != LC_OK || lc_rbf_get_info(v, &in) != LC_OK ||
        lc_tf_preset(dev, "heat", 1, 1.0f / in.max_width, &tf) != LC_OK) {
        fprintf(stderr, "bench_rbf: %s\n", lc_last_error());
        lc_volume_destroy(v);
        return -1;
    }
    float *img = malloc(sizeof(float) * 4 * (size_t)size * size);
    double fps[64];
    lc_render_stats rs = {0};
    lc_render_desc rd = {.width = size, .height = size, .tf = tf, .volume = v,
                         .camera = {LC_PERSPECTIVE, {1.2f, 1.5f, 4.2f}, {0, 0, 0}, {0, 1, 0}, 40.0f, 0.0f}};
    int ok = img != NULL;
    for (int r = -1; ok && r < repeats; r++) {
        ok = lc_render(dev, &rd, img, &rs) == LC_OK;
        if (r >= 0) fps[r] = 1.0 / rs.seconds;
    }
    if (ok) {
        qsort(fps, (size_t)repeats, sizeof(double), cmpd);
        int oct = in.accel == LC_RBF_ACCEL_OCTREE;
        lc_target t;
        int threads;
        lc_device_target(dev, &t), lc_device_threads(dev, &threads);
        printf("rbf n=%zu layout=%s accel=%s cell_max=%d target=%s threads=%d size=%d build_s=%.4f bytes=%zu "
               "cells=%d refs=%zu fps=%.3f fps_min=%.3f fps_max=%.3f gaussians=%llu\n",
               st->n, layout, oct ? "octree" : "bvh", oct ? in.cell_max : 0, lc_target_name(t), threads, size,
               oct ? in.octree_seconds : in.build_seconds - in.octree_seconds,
               oct ? in.octree_bytes : in.bvh_bytes + in.data_bytes, in.octree_cells, in.octree_refs,
               fps[repeats / 2], fps[0], fps[repeats - 1], (unsigned long long)rs.kernel_evals);
        fflush(stdout);
    } else fprintf(stderr, "bench_rbf: %s\n", lc_last_error());
    free(img);
    lc_tf_destroy(tf);
    lc_volume_destroy(v);
    return ok ? 0 : -1;
}

static void usage(void)
{
    printf("bench_rbf [--quick] [--n 1000,10000,100000] [--layouts uniform,clustered] [--cells 16]\n"
           "          [--size 1024] [--repeats 5]\n"
           "  BVH against octree (one line each per cell_max) per set; --quick: n 1000, 64 px, 1 repeat\n");
}

int main(int argc, char **argv)
{
    char nl[256] = "1000,10000,100000", ll[64] = "uniform,clustered", cl[128] = "16";
    int size = 1024, repeats = 5;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quick")) strcpy(nl, "1000"), size = 64, repeats = 1;
        else if (!strcmp(a, "--n") && v) snprintf(nl, sizeof nl, "%s", v), i++;
        else if (!strcmp(a, "--layouts") && v) snprintf(ll, sizeof ll, "%s", v), i++;
        else if (!strcmp(a, "--cells") && v) snprintf(cl, sizeof cl, "%s", v), i++;
        else if (!strcmp(a, "--size") && v) size = atoi(v), i++;
        else if (!strcmp(a, "--repeats") && v) repeats = atoi(v), i++;
        else {
            usage();
            return strcmp(a, "--help") ? 2 : 0;
        }
    }
    if (size < 1 || size > 8192 || repeats < 1 || repeats > 64) {
        fprintf(stderr, "bench_rbf: --size 1..8192, --repeats 1..64\n");
        return 2;
    }
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return fprintf(stderr, "bench_rbf: %s\n", lc_last_error()), 1;
    int fails = 0;
    for (char *np = strtok(nl, ","); np; np = strtok(NULL, ",")) {
        size_t n = strtoull(np, NULL, 10);
        char lcopy[64];
        snprintf(lcopy, sizeof lcopy, "%s", ll);
        for (char *lp = lcopy, *lay; (lay = strsep(&lp, ","));) {
            set st;
            if (n < 1 || n > 10000000 || make_set(&st, n, !strcmp(lay, "clustered"), 12345u + n) != 0) {
                fprintf(stderr, "bench_rbf: bad n %s\n", np);
                return 2;
            }
            fails += run_case(dev, &st, lay, LC_RBF_ACCEL_BVH, 0, size, repeats) != 0;
            char ccopy[128];
            snprintf(ccopy, sizeof ccopy, "%s", cl);
            for (char *cp = ccopy, *c; (c = strsep(&cp, ","));)
                fails += run_case(dev, &st, lay, LC_RBF_ACCEL_OCTREE, atoi(c), size, repeats) != 0;
            free(st.c), free(st.s), free(st.w);
        }
    }
    lc_device_destroy(dev);
    return fails ? 1 : 0;
}
