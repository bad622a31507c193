/* Structured-volume benchmark (Knoll et al. 2011, Fig. 5/6, Table 1 style):
 * one machine-readable line per case with the median fps of the repeats and
 * its spread. Cases are the cross product of the lists given (see --help).
 * Volumes: the real ones under DATA/volumes and procedural uint8 cubes
 * ("proc512", "proc1024": a gyroid-like lattice inside a sphere, air outside;
 * deterministic, no seed needed; "blob256": a sum of Gaussian blobs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "host/internal.h"
#include "lanecast/lanecast.h"

/* Stage-profile kernel variants (bench/grid_prof.c, meson prof_masks): each
 * replaces one more stage than the one before. Each variant library defines
 * the grid kind's kernel sub-table lc_kkind_grid_prof_<target>_<i> (BVH and
 * brute), for up to two targets LC_PROF_T0/T1 (avx2 and avx512 when built). */
#define NPROF 7
#define PROF_NAME2(t, i) lc_kkind_grid_prof_##t##_##i
#define PROF_NAME(t, i) PROF_NAME2(t, i)
#define PROF_DECLS(t)                                                                                                   \
    extern const lc_kkind PROF_NAME(t, 0), PROF_NAME(t, 1), PROF_NAME(t, 2), PROF_NAME(t, 3), PROF_NAME(t, 4),         \
        PROF_NAME(t, 5), PROF_NAME(t, 6);
#define PROF_TABLE(t)                                                                                                   \
    {&PROF_NAME(t, 0), &PROF_NAME(t, 1), &PROF_NAME(t, 2), &PROF_NAME(t, 3), &PROF_NAME(t, 4), &PROF_NAME(t, 5),       \
     &PROF_NAME(t, 6)}
PROF_DECLS(LC_PROF_T0)
#ifdef LC_PROF_T1
PROF_DECLS(LC_PROF_T1)
#endif
static const struct {
    const char *target;
    const lc_kkind *kind[NPROF];
} prof_sets[] = {
    {LC_PROF_T0_NAME, PROF_TABLE(LC_PROF_T0)},
#ifdef LC_PROF_T1
    {LC_PROF_T1_NAME, PROF_TABLE(LC_PROF_T1)},
#endif
};
#define NPROF_SETS (int)(sizeof prof_sets / sizeof prof_sets[0])
/* stage removed between variant i-1 and i (variant 0: all stages, no early termination) */
static const char *const prof_stage[NPROF] = {"total", "fetch", "interpolation", "classification", "shading", "blending",
                                              "sample_loop"};

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CPU time of the whole process (every render thread): on a shared machine
 * it moves much less with the load than wall time. */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

#define MAXL 16
typedef struct list {
    int n;
    char *v[MAXL];
} list;

static void split(list *l, char *s)
{
    l->n = 0;
    for (char *t = strtok(s, ","); t && l->n < MAXL; t = strtok(NULL, ",")) l->v[l->n++] = t;
}

static lc_grid_layout layout = LC_LAYOUT_DEFAULT;
static int brick; /* BVH leaf side (0: the library default) */

/* "proc512" etc.: the gyroid lattice as uint8; "proc512u16": the same
 * values times 257 as uint16, "proc512f32" as float32 (no pair copy: the
 * bricked or linear voxels). "proc1024x1024x256u16": a box of those nodes
 * (the lattice's period and sphere scale with each axis' size), e.g. to set
 * a power-of-two row width (1024) against an odd one (1040). */
static lc_status procedural(lc_device *dev, const int n[3], lc_value_type type, lc_volume **out)
{
    int u16 = type == LC_VALUE_UINT16, f32 = type == LC_VALUE_FLOAT32;
    size_t count = (size_t)n[0] * n[1] * n[2];
    uint8_t *v = malloc(count * (f32 ? 4 : u16 ? 2 : 1));
    float *ax = malloc(sizeof(float) * 3 * ((size_t)n[0] + n[1] + n[2]));
    if (!v || !ax) {
        free(v), free(ax);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    float *s[3], *c[3], *q[3];
    for (int a = 0, o = 0; a < 3; o += 3 * n[a], a++) {
        s[a] = ax + o, c[a] = s[a] + n[a], q[a] = c[a] + n[a];
        for (int i = 0; i < n[a]; i++) {
            double x = (double)i / (n[a] - 1);
            s[a][i] = (float)sin(x * 6.2831853 * 4), c[a][i] = (float)cos(x * 6.2831853 * 4);
            q[a][i] = (float)((x - 0.5) * (x - 0.5));
        }
    }
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++) {
            uint8_t *row = v + ((size_t)k * n[1] + j) * n[0];
            float qjk = q[1][j] + q[2][k];
            for (int i = 0; i < n[0]; i++) {
                /* gyroid, in [-1.5, 1.5] */
                float g = s[0][i] * c[1][j] + s[1][j] * c[2][k] + s[2][k] * c[0][i];
                float r2 = q[0][i] + qjk;
                row[i] = r2 < 0.2f ? (uint8_t)(127.5f + 85.0f * g) : 0;
            }
        }
    free(ax);
    if (u16) { /* widen in place, from the end */
        uint16_t *w = (uint16_t *)(void *)v;
        for (size_t e = count; e-- > 0;) w[e] = (uint16_t)(v[e] * 257u);
    }
    if (f32) {
        float *w = (float *)(void *)v;
        for (size_t e = count; e-- > 0;) w[e] = (float)v[e] / 255.0f;
    }
    lc_grid_desc d = {.size = {n[0], n[1], n[2]}, .type = type, .data = v, .layout = layout, .brick = brick};
    lc_status st = lc_grid_create(dev, &d, out);
    free(v);
    return st;
}

/* "blob256" etc.: a uint8 cube holding a sum of 24 Gaussian blobs (centres,
 * radii and weights from a fixed LCG, so no seed is needed) scaled to
 * 0..255, clamped; most of the cube is air (value 0 far from every blob). */
static lc_status blobs(lc_device *dev, int n, lc_volume **out)
{
    enum { NB = 24 };
    float c[NB][3], r[NB], w[NB];
    uint32_t s = 12345u;
#define LCG() ((s = s * 1664525u + 1013904223u) >> 8) / 16777216.0f
    for (int b = 0; b < NB; b++) {
        for (int a = 0; a < 3; a++) c[b][a] = 0.2f + 0.6f * LCG();
        r[b] = 0.05f + 0.10f * LCG();
        w[b] = 0.5f + 0.5f * LCG();
    }
#undef LCG
    uint8_t *v = malloc((size_t)n * n * n);
    if (!v) return LC_ERROR_OUT_OF_MEMORY;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                float x = (float)i / (float)(n - 1), y = (float)j / (float)(n - 1), z = (float)k / (float)(n - 1), sum = 0.0f;
                for (int b = 0; b < NB; b++) {
                    float dx = x - c[b][0], dy = y - c[b][1], dz = z - c[b][2], q = (dx * dx + dy * dy + dz * dz) / (r[b] * r[b]);
                    if (q < 9.0f) sum += w[b] * expf(-q);
                }
                v[((size_t)k * n + j) * n + i] = (uint8_t)(255.0f * fminf(sum, 1.0f) + 0.5f);
            }
    lc_grid_desc d = {.size = {n, n, n}, .type = LC_VALUE_UINT8, .data = v, .layout = layout, .brick = brick};
    lc_status st = lc_grid_create(dev, &d, out);
    free(v);
    return st;
}

static int prof_bad; /* a variant took other samples than the full one: the profile is void */

/* Stage profile of one case: the shipped kernel (default alpha_stop) for
 * reference, then the variants round-robin `repeats` times so that load
 * changes hit every variant alike; medians; the time of a stage is the
 * median time of the variant before its removal minus the one after. */
static void run_profile(lc_device *dev, const lc_render_desc *d0, const char *vn, int W, const char *view, const char *shade,
                        const char *meth, int nth, int repeats)
{
    const lc_kkind *const *prof_kind = NULL;
    for (int i = 0; i < NPROF_SETS; i++) {
        lc_target pt;
        if (lc_target_from_name(prof_sets[i].target, &pt) == LC_OK && dev->target == pt) prof_kind = prof_sets[i].kind;
    }
    if (!prof_kind) {
        printf("# profile: variants are built for %s%s%s, device runs %s: skipped\n", prof_sets[0].target,
               NPROF_SETS > 1 ? " and " : "", NPROF_SETS > 1 ? prof_sets[NPROF_SETS - 1].target : "",
               lc_target_name(dev->target));
        return;
    }
    float *rgba = malloc(sizeof(float) * 4 * (size_t)W * W);
    lc_render_desc d = *d0;
    lc_render_stats st;
    double shipped[64], ts[NPROF][64];
    uint64_t samples[NPROF];
    int n = repeats < 64 ? repeats : 64;
    const lc_ktable *orig = dev->kt;
    lc_ktable kt = *orig;
    lc_render(dev, &d, rgba, &st); /* warm-up */
    /* CPU time of the process (all render threads): on the shared machine wall
     * time moved by up to 3x with the load, which voided the differences */
    for (int r = 0; r < n; r++) {
        double a = cpu_now();
        lc_render(dev, &d, rgba, &st);
        shipped[r] = cpu_now() - a;
    }
    uint64_t shipped_samples = st.samples;
    d.alpha_stop = 1.0f;
    for (int r = -1; r < n; r++) /* r = -1: warm-up round */
        for (int v = 0; v < NPROF; v++) {
            kt.kind[LC_KKIND_GRID] = prof_kind[v];
            dev->kt = &kt;
            double a = cpu_now();
            lc_render(dev, &d, rgba, &st);
            if (r >= 0) ts[v][r] = cpu_now() - a;
            samples[v] = st.samples;
            dev->kt = orig;
        }
    qsort(shipped, (size_t)n, sizeof(double), cmpd);
    double med[NPROF], lo[NPROF], hi[NPROF];
    for (int v = 0; v < NPROF; v++) {
        qsort(ts[v], (size_t)n, sizeof(double), cmpd);
        med[v] = ts[v][n / 2], lo[v] = ts[v][0], hi[v] = ts[v][n - 1];
    }
    printf("gridprof volume=%s size=%d view=%s shade=%s method=%s target=%s threads=%d reps=%d shipped_ms=%.1f "
           "shipped_msamples=%.2f nostop_msamples=%.2f",
           vn, W, view, shade, meth, lc_target_name(dev->target), nth, n, 1e3 * shipped[n / 2], (double)shipped_samples / 1e6,
           (double)samples[0] / 1e6);
    /* same samples in every variant that still samples: the subtraction compares like with like */
    int same = 1;
    for (int v = 1; v < NPROF - 1; v++) same &= samples[v] == samples[0];
    printf(" same_samples=%s", same ? "yes" : "NO");
    if (!same) prof_bad = 1;
    for (int v = 0; v < NPROF; v++) printf(" v%d_ms=%.1f v%d_min=%.1f v%d_max=%.1f", v, 1e3 * med[v], v, 1e3 * lo[v], v, 1e3 * hi[v]);
    for (int v = 1; v < NPROF; v++) printf(" %s_ms=%.1f", prof_stage[v], 1e3 * (med[v - 1] - med[v]));
    printf(" rest_ms=%.1f\n", 1e3 * med[NPROF - 1]);
    fflush(stdout);
    free(rgba);
}

static const char help[] =
    "usage: bench_grid [options]\n"
    "  --data DIR          shared data folder (default ../shared/data)\n"
    "  --volumes a,b,...   engine, neghip, headsq, hydrogen, embryo, HeadMRVolume, proc512, proc1024,\n"
    "                      blob256 (any procN / blobN; procNu16 / procNf32: uint16 / float32; procWxHxD[u16|f32]:\n"
    "                      a box, e.g. proc1024x1024x256u16 against proc1040x1024x256u16; default engine)\n"
    "  --sizes 512,1024    image sides (default 512)\n"
    "  --views far,medium,close (default medium)\n"
    "  --shades none,diffuse,phong (default none)\n"
    "  --methods brute,bvh (default brute,bvh)\n"
    "  --targets scalar,sse4,avx2,avx512,avx512_8 (default: the widest supported)\n"
    "  --threads 1,2       (default: all CPUs)\n"
    "  --packets 8,1       packet side (8 = 8x8, 1 = lane width; default 8); the BVH traverses\n"
    "                      groups of side x (rows / 256, 1-4) rays, at most 32 (grid_common.h)\n"
    "  --heuristics on|off (default on)\n"
    "  --layout linear|bricked  voxel layout (default: the library's, linear except owned float32: bricked 4^3)\n"
    "  --brick L           BVH leaf side 1, 2, 4, 8 or 16 (default: the library's choice by size)\n"
    "  --repeats N         renders per case after one warm-up (default 5)\n"
    "  --max-seconds S     stop repeating a case after S seconds (default 10)\n"
    "  --dir X,Y,Z         the eye's direction from the centre (default 0.5,0.4,0.767: oblique), e.g.\n"
    "                      --dir 0,0,1 to look down -z along the volume's rows of planes\n"
    "  --mode M            dvr (default), mip, or iso:V (the iso-surface at value V in the volume's units,\n"
    "                      e.g. iso:128); shading applies to dvr and iso\n"
    "  --profile           stage profile (CPU ms) instead of fps: the kernel variants of bench/grid_prof.c\n"
    "                      (avx2 and avx512 when compiled), repeats interleaved; see docs/bench/grid.md\n";

int main(int argc, char **argv)
{
    char dflt_vol[] = "engine", dflt_size[] = "512", dflt_view[] = "medium", dflt_shade[] = "none",
         dflt_meth[] = "brute,bvh", dflt_pk[] = "8", dflt_thr[] = "0", dflt_tgt[] = "auto";
    const char *data = "../shared/data";
    list vols, sizes, views, shades, meths, tgts, thrs, pks;
    split(&vols, dflt_vol), split(&sizes, dflt_size), split(&views, dflt_view), split(&shades, dflt_shade);
    split(&meths, dflt_meth), split(&tgts, dflt_tgt), split(&thrs, dflt_thr), split(&pks, dflt_pk);
    int repeats = 5, heur = 1, profile = 0;
    const char *mode = "dvr";
    float dir[3] = {0.5f, 0.4f, 0.767f};
    double max_s = 10;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help")) {
            fputs(help, stdout);
            return 0;
        }
        if (!strcmp(a, "--profile")) {
            profile = 1;
            continue;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "bench_grid: %s needs a value\n", a);
            return 2;
        }
        char *v = argv[++i];
        if (!strcmp(a, "--data")) data = v;
        else if (!strcmp(a, "--volumes")) split(&vols, v);
        else if (!strcmp(a, "--sizes")) split(&sizes, v);
        else if (!strcmp(a, "--views")) split(&views, v);
        else if (!strcmp(a, "--shades")) split(&shades, v);
        else if (!strcmp(a, "--methods")) split(&meths, v);
        else if (!strcmp(a, "--targets")) split(&tgts, v);
        else if (!strcmp(a, "--threads")) split(&thrs, v);
        else if (!strcmp(a, "--packets")) split(&pks, v);
        else if (!strcmp(a, "--brick")) brick = atoi(v);
        else if (!strcmp(a, "--heuristics")) heur = !strcmp(v, "on");
        else if (!strcmp(a, "--repeats")) repeats = atoi(v);
        else if (!strcmp(a, "--layout")) layout = !strcmp(v, "linear") ? LC_LAYOUT_LINEAR : LC_LAYOUT_BRICKED;
        else if (!strcmp(a, "--max-seconds")) max_s = atof(v);
        else if (!strcmp(a, "--mode")) mode = v;
        else if (!strcmp(a, "--dir")) {
            if (sscanf(v, "%f,%f,%f", &dir[0], &dir[1], &dir[2]) != 3 || !(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2] > 0)) {
                fprintf(stderr, "bench_grid: --dir %s: expected X,Y,Z, not all zero\n", v);
                return 2;
            }
            float l = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            dir[0] /= l, dir[1] /= l, dir[2] /= l;
        }
        else {
            fprintf(stderr, "bench_grid: unknown option %s\n", a);
            return 2;
        }
    }
    if (repeats < 1) repeats = 1;
    lc_mode rmode = LC_MODE_DVR;
    float iso = 0.0f;
    if (!strcmp(mode, "mip")) rmode = LC_MODE_MIP;
    else if (!strncmp(mode, "iso:", 4)) rmode = LC_MODE_ISO, iso = (float)atof(mode + 4);
    else if (strcmp(mode, "dvr")) {
        fprintf(stderr, "bench_grid: --mode %s: expected dvr, mip or iso:V\n", mode);
        return 2;
    }
    if (profile && rmode != LC_MODE_DVR) {
        fprintf(stderr, "bench_grid: --profile measures dvr frames only\n");
        return 2;
    }
    lc_device *dev0 = NULL;
    if (lc_device_create(&(lc_device_desc){.threads = 1}, &dev0) != LC_OK) return 1;
    for (int vi = 0; vi < vols.n; vi++) {
        lc_volume *g = NULL;
        const char *vn = vols.v[vi];
        double t0 = now();
        lc_status s;
        if (!strncmp(vn, "proc", 4)) {
            int n[3], got = sscanf(vn + 4, "%dx%dx%d", &n[0], &n[1], &n[2]);
            if (got != 3) n[1] = n[2] = n[0];
            if (got < 1 || n[0] < 2 || n[1] < 2 || n[2] < 2) {
                printf("# skip volume=%s: expected procN or procWxHxD (sizes >= 2)\n", vn);
                continue;
            }
            s = procedural(dev0, n, strstr(vn, "u16") ? LC_VALUE_UINT16 : strstr(vn, "f32") ? LC_VALUE_FLOAT32 : LC_VALUE_UINT8, &g);
        }
        else if (!strncmp(vn, "blob", 4)) s = blobs(dev0, atoi(vn + 4), &g);
        else {
            char p[1024];
            snprintf(p, sizeof p, "%s/volumes/%s.%s", data, vn, strcmp(vn, "HeadMRVolume") ? "nhdr" : "mhd");
            char bs[16];
            snprintf(bs, sizeof bs, "%d", brick);
            lc_option lo_[2] = {{"brick", bs}, {"layout", layout == LC_LAYOUT_LINEAR ? "linear" : "bricked"}};
            int no = brick ? 1 : 0;
            if (layout != LC_LAYOUT_DEFAULT) lo_[no++] = lo_[1];
            s = lc_volume_load(dev0, p, &(lc_load_desc){.options = lo_, .noptions = no}, &g);
        }
        if (s != LC_OK) {
            printf("# skip volume=%s: %s\n", vn, lc_last_error());
            continue;
        }
        lc_grid_info in;
        lc_grid_get_info(g, &in);
        /* heuristics: the grid's parameters (default deltas, or eqs. 5-7 off) */
        if (!heur) lc_grid_set_params(g, &(lc_grid_params){.delta_c = -1, .delta_p = -1, .delta_sv = -1});
        printf("# volume=%s dims=%dx%dx%d load_s=%.3f bvh_L=%d bvh_nodes=%llu bvh_MB=%.2f bvh_build_s=%.3f "
               "layout_overhead_MB=%.3f\n",
               vn, in.size[0], in.size[1], in.size[2], now() - t0, in.brick, (unsigned long long)in.bvh_nodes,
               (double)in.bvh_bytes / 1e6, in.bvh_build_seconds, (double)in.layout_overhead_bytes / 1e6);
        fflush(stdout);
        float lo[3] = {in.bounds.lo.x, in.bounds.lo.y, in.bounds.lo.z}, hi[3] = {in.bounds.hi.x, in.bounds.hi.y, in.bounds.hi.z};
        float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
        /* a TF that hides the air (transparent below 30% of the range) */
        float color[] = {0, 0.2f, 0.3f, 0.9f, 0.5f, 0.9f, 0.5f, 0.2f, 1, 1, 1, 0.9f};
        float op[] = {0, 0, 0.3f, 0, 0.6f, 0.4f * 16 / diag, 1, 16 / diag};
        lc_tf_field tfd = {.color = color, .ncolor = 3, .opacity = op, .nopacity = 4};
        lc_tf *tf = NULL;
        lc_tf_create(dev0, &tfd, 1, &tf);
        for (int ti = 0; ti < tgts.n; ti++)
            for (int hi_ = 0; hi_ < thrs.n; hi_++) {
                lc_target tg = LC_TARGET_AUTO;
                if (strcmp(tgts.v[ti], "auto") && lc_target_from_name(tgts.v[ti], &tg) != LC_OK) continue;
                lc_device *dev = NULL;
                if (lc_device_create(&(lc_device_desc){.target = tg, .threads = atoi(thrs.v[hi_])}, &dev) != LC_OK) {
                    printf("# skip target=%s: %s\n", tgts.v[ti], lc_last_error());
                    continue;
                }
                lc_target at;
                int nth;
                lc_device_target(dev, &at);
                lc_device_threads(dev, &nth);
                for (int si = 0; si < sizes.n; si++)
                    for (int wi = 0; wi < views.n; wi++)
                        for (int shi = 0; shi < shades.n; shi++)
                            for (int pi = 0; pi < pks.n; pi++)
                                for (int mi = 0; mi < meths.n; mi++) {
                                    int W = atoi(sizes.v[si]);
                                    const char *view = views.v[wi];
                                    float dist = !strcmp(view, "far") ? 2.5f : !strcmp(view, "close") ? 0.75f : 1.3f;
                                    lc_render_desc d = {.width = W, .height = W, .tf = tf, .volume = g, .packet = atoi(pks.v[pi])};
                                    d.camera.at = (lc_vec3){0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
                                    d.camera.eye = (lc_vec3){d.camera.at.x + dist * diag * dir[0], d.camera.at.y + dist * diag * dir[1],
                                                             d.camera.at.z + dist * diag * dir[2]};
                                    d.shading = !strcmp(shades.v[shi], "phong") ? LC_SHADE_PHONG
                                                : !strcmp(shades.v[shi], "diffuse") ? LC_SHADE_DIFFUSE : LC_SHADE_NONE;
                                    d.method = !strcmp(meths.v[mi], "brute") ? LC_METHOD_BRUTE : LC_METHOD_BVH;
                                    d.mode = rmode, d.iso = iso;
                                    if (profile) {
                                        run_profile(dev, &d, vn, W, view, shades.v[shi], meths.v[mi], nth, repeats);
                                        continue;
                                    }
                                    float *rgba = malloc(sizeof(float) * 4 * (size_t)W * W);
                                    lc_render_stats st;
                                    if (lc_render(dev, &d, rgba, &st) != LC_OK) { /* warm-up */
                                        printf("# error: %s\n", lc_last_error());
                                        free(rgba);
                                        continue;
                                    }
                                    double ts[64], cs[64];
                                    int n = 0;
                                    double start = now();
                                    while (n < repeats && n < 64) {
                                        double a = now(), ca = cpu_now();
                                        lc_render(dev, &d, rgba, &st);
                                        cs[n] = cpu_now() - ca;
                                        ts[n++] = now() - a;
                                        if (now() - start > max_s) break;
                                    }
                                    qsort(ts, (size_t)n, sizeof *ts, cmpd);
                                    qsort(cs, (size_t)n, sizeof *cs, cmpd);
                                    double med = ts[n / 2];
                                    printf("grid volume=%s size=%d view=%s shade=%s method=%s target=%s threads=%d packet=%s "
                                           "heuristics=%s fps=%.3f fps_min=%.3f fps_max=%.3f ms=%.1f reps=%d "
                                           "msamples=%.2f nodes=%llu leaves=%llu cpu_ms=%.1f cpu_ms_min=%.1f cpu_ms_max=%.1f mode=%s\n",
                                           vn, W, view, shades.v[shi], meths.v[mi], lc_target_name(at), nth, pks.v[pi],
                                           heur ? "on" : "off", 1.0 / med, 1.0 / ts[n - 1], 1.0 / ts[0], 1e3 * med, n,
                                           (double)st.samples / 1e6, (unsigned long long)st.nodes, (unsigned long long)st.leaves,
                                           1e3 * cs[n / 2], 1e3 * cs[0], 1e3 * cs[n - 1], mode);
                                    fflush(stdout);
                                    free(rgba);
                                }
                lc_device_destroy(dev);
            }
        lc_tf_destroy(tf);
        lc_volume_destroy(g);
    }
    lc_device_destroy(dev0);
    return prof_bad;
}
