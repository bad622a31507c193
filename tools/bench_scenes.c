/* lanecast bench: the scenes (procedural with fixed seeds, or the shared
 * real data sets) and the three views. Everything goes through the public
 * API; a scene is built once and rendered by every target's device. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "bench_common.h"
#include "cli.h"

const char bench_scene_help[] =
    "      procedural particles (fixed seed, 1 particle per 8 cubic units; N up to 1e8):\n"
    "        uniform:N   radii uniform in [0.6, 1.2]\n"
    "        heavy:N     heavy-tailed radii: Pareto (alpha 2.5) from 0.4, capped at 12\n"
    "        cluster:N   dense: 16 Gaussian clusters (sd = side / 24), radii [0.3, 0.6]\n"
    "      procedural grids:  grid:N   uint8 gyroid lattice in a sphere, N^3 nodes (256, 512, 1024; N <= 1290)\n"
    "      procedural RBF sets (as bench/bench_rbf.c): rbf:N uniform, rbfc:N in 8 clusters\n"
    "      demo        the scene of lanecast demo (a two-field particle helix in a shell)\n"
    "      real data (DATA = --data; skipped with a note when absent):\n"
    "        1tii 1tw7 bigbox adk galaxy lcdm   (particles/)\n"
    "        engine neghip headsq hydrogen embryo headmr   (volumes/)\n"
    "      any file lanecast reads:  file:PATH\n";

typedef struct real_set {
    const char *name, *path, *companion;
} real_set;

static const real_set reals[] = {
    {"1tii", "particles/1tii.pdb", NULL},
    {"1tw7", "particles/1tw7_solvated.pdb", NULL},
    {"bigbox", "particles/bigbox_water.gro.gz", NULL},
    {"adk", "particles/adk.dcd", "particles/adk.psf"},
    {"galaxy", "particles/gadget_galaxy.dat", NULL},
    {"lcdm", "particles/gadget_lcdm_gas.dat", NULL},
    {"engine", "volumes/engine.nhdr", NULL},
    {"neghip", "volumes/neghip.nhdr", NULL},
    {"headsq", "volumes/headsq.nhdr", NULL},
    {"hydrogen", "volumes/hydrogen.nhdr", NULL},
    {"embryo", "volumes/embryo.nhdr", NULL},
    {"headmr", "volumes/HeadMRVolume.mhd", NULL},
};
#define NREAL (sizeof reals / sizeof reals[0])

static const real_set *find_real(const char *name)
{
    for (size_t i = 0; i < NREAL; i++)
        if (!strcmp(reals[i].name, name)) return &reals[i];
    return NULL;
}

/* "kind:N" with N a count like 1e5; returns the kind prefix index or -1. */
static const char *const prefixes[] = {"uniform:", "heavy:", "cluster:", "grid:", "rbf:", "rbfc:"};
enum { P_UNIFORM, P_HEAVY, P_CLUSTER, P_GRID, P_RBF, P_RBFC, P_COUNT };

static int parse_proc(const char *name, double *n)
{
    for (int p = 0; p < P_COUNT; p++) {
        size_t l = strlen(prefixes[p]);
        if (strncmp(name, prefixes[p], l)) continue;
        char *end;
        *n = strtod(name + l, &end);
        if (*end || !(*n >= 1) || !isfinite(*n)) return -1;
        return p;
    }
    return -1;
}

int bench_scene_known(const char *name)
{
    double n;
    return find_real(name) || parse_proc(name, &n) >= 0 || (!strncmp(name, "file:", 5) && name[5]) ||
           !strcmp(name, "demo");
}

/* xorshift64*: the one generator of the procedural sets */
static uint64_t rng_state;
static double urand(void)
{
    rng_state ^= rng_state >> 12, rng_state ^= rng_state << 25, rng_state ^= rng_state >> 27;
    return (double)((rng_state * 0x2545f4914f6cdd1dull) >> 11) / 9007199254740992.0;
}
static double nrand(void) { return sqrt(-2.0 * log(1.0 - urand())) * cos(6.283185307179586 * urand()); }

static lc_status make_particles(lc_device *dev, int p, size_t n, bench_scene *sc)
{
    float *xyz = malloc(sizeof(float) * 3 * n), *r = malloc(sizeof(float) * n);
    if (!xyz || !r) {
        free(xyz), free(r);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    double side = 2.0 * cbrt((double)n), c[16][3];
    rng_state = 0x9e3779b97f4a7c15ull + (uint64_t)p;
    for (int k = 0; k < 16; k++)
        for (int a = 0; a < 3; a++) c[k][a] = side * (0.15 + 0.7 * urand());
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++)
            xyz[3 * i + a] = (float)(p == P_CLUSTER ? c[i % 16][a] + side / 24.0 * nrand() : side * urand());
        if (p == P_UNIFORM) r[i] = (float)(0.6 + 0.6 * urand());
        else if (p == P_HEAVY) r[i] = (float)fmin(0.4 * pow(1.0 - urand(), -1.0 / 2.5), 12.0);
        else r[i] = (float)(0.3 + 0.3 * urand());
    }
    snprintf(sc->source, sizeof sc->source, "procedural particles (%s radii), xorshift64* seed 0x9e3779b97f4a7c15+%d, side %.4g",
             p == P_UNIFORM ? "uniform" : p == P_HEAVY ? "heavy-tailed" : "clustered, small", p, side);
    lc_status s = lc_particles_create(dev, &(lc_particles_desc){.count = n, .positions = xyz, .radii = r}, &sc->vol);
    free(xyz);
    free(r);
    return s;
}

/* bench/bench_grid.c's gyroid lattice inside a sphere, air outside */
static lc_status make_grid(lc_device *dev, int n, bench_scene *sc)
{
    uint8_t *v = malloc((size_t)n * n * n);
    float *s = malloc(sizeof(float) * (size_t)n * 3);
    if (!v || !s) {
        free(v), free(s);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    float *c = s + n, *q = c + n;
    for (int i = 0; i < n; i++) {
        double x = (double)i / (n - 1);
        s[i] = (float)sin(x * 6.2831853 * 4), c[i] = (float)cos(x * 6.2831853 * 4);
        q[i] = (float)((x - 0.5) * (x - 0.5));
    }
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++) {
            uint8_t *row = v + ((size_t)k * n + j) * n;
            for (int i = 0; i < n; i++) {
                float g = s[i] * c[j] + s[j] * c[k] + s[k] * c[i];
                row[i] = q[i] + q[j] + q[k] < 0.2f ? (uint8_t)(127.5f + 85.0f * g) : 0;
            }
        }
    free(s);
    snprintf(sc->source, sizeof sc->source, "procedural uint8 %d^3 gyroid in a sphere (bench_grid's proc%d)", n, n);
    lc_status st = lc_grid_create(dev, &(lc_grid_desc){.size = {n, n, n}, .type = LC_VALUE_UINT8, .data = v}, &sc->vol);
    free(v);
    return st;
}

/* bench/bench_rbf.c's sets: centres in [-1, 1]^3 or 8 clusters, widths
 * 0.5 n^(-1/3) U(0.5, 1.5), weights U(-0.5, 1). */
static lc_status make_rbf(lc_device *dev, int clustered, size_t n, bench_scene *sc)
{
    float *c = malloc(sizeof(float) * 3 * n), *w = malloc(sizeof(float) * n), *s = malloc(sizeof(float) * n);
    if (!c || !w || !s) {
        free(c), free(w), free(s);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    rng_state = 0x2545f4914f6cdd1dull + (uint64_t)clustered;
    double cc[8][3], s0 = 0.5 * pow((double)n, -1.0 / 3.0);
    for (int k = 0; k < 8; k++)
        for (int a = 0; a < 3; a++) cc[k][a] = -0.7 + 1.4 * urand();
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            double x = clustered ? cc[i % 8][a] + 0.12 * nrand() : -1.0 + 2.0 * urand();
            c[3 * i + a] = (float)fmin(fmax(x, -1.0), 1.0);
        }
        s[i] = (float)(s0 * (0.5 + urand()));
        w[i] = (float)(-0.5 + 1.5 * urand());
    }
    snprintf(sc->source, sizeof sc->source, "procedural RBF set (%s), xorshift64* seed 0x2545f4914f6cdd1d+%d",
             clustered ? "8 clusters" : "uniform", clustered);
    lc_status st = lc_rbf_create(dev, &(lc_rbf_desc){.count = n, .centres = c, .widths = s, .weights = w}, &sc->vol);
    free(c), free(w), free(s);
    return st;
}

static void fill_info(bench_scene *sc)
{
    sc->kind = lc_volume_kind(sc->vol);
    lc_volume_get_info(sc->vol, &sc->info);
    if (sc->kind == LC_KIND_PARTICLES) {
        lc_particles_info pi;
        lc_particles_get_info(sc->vol, &pi);
        sc->count = pi.count, sc->build_seconds = pi.build_seconds, sc->bvh_bytes = pi.bvh_bytes;
        sc->data_bytes = pi.data_bytes, sc->max_radius = pi.max_radius;
    } else if (sc->kind == LC_KIND_GRID) {
        lc_grid_info gi;
        lc_grid_get_info(sc->vol, &gi);
        sc->count = (size_t)gi.size[0] * (size_t)gi.size[1] * (size_t)gi.size[2];
        sc->build_seconds = gi.bvh_build_seconds, sc->bvh_bytes = (size_t)gi.bvh_bytes;
        sc->data_bytes = (size_t)gi.layout_bytes;
    } else if (sc->kind == LC_KIND_RBF) {
        lc_rbf_info ri;
        lc_rbf_get_info(sc->vol, &ri);
        sc->count = ri.count, sc->build_seconds = ri.build_seconds, sc->bvh_bytes = ri.bvh_bytes + ri.octree_bytes;
        sc->data_bytes = ri.data_bytes, sc->max_radius = ri.max_width;
    }
}

lc_status bench_scene_make(lc_device *dev, const char *name, const char *data_dir, bench_scene *sc, char *note,
                           size_t note_size)
{
    memset(sc, 0, sizeof *sc);
    snprintf(sc->name, sizeof sc->name, "%s", name);
    double n = 0, t0 = bench_now();
    int p = parse_proc(name, &n);
    const real_set *rs = find_real(name);
    lc_status s;
    if (p >= 0 && p != P_GRID && n > 1e8) { /* checked before allocating: 1e8 particles take ~5 GB with the BVH */
        snprintf(note, note_size, "scene %s: at most 1e8 particles or RBFs", name);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    if (p == P_UNIFORM || p == P_HEAVY || p == P_CLUSTER) s = make_particles(dev, p, (size_t)n, sc);
    else if (p == P_GRID) {
        if (n < 2 || n > 1290) { /* 1290^3 < 2^31 values */
            snprintf(note, note_size, "scene %s: a grid side from 2 to 1290", name);
            return LC_ERROR_INVALID_ARGUMENT;
        }
        s = make_grid(dev, (int)n, sc);
    } else if (p == P_RBF || p == P_RBFC) s = make_rbf(dev, p == P_RBFC, (size_t)n, sc);
    else if (!strcmp(name, "demo")) {
        lc_tf *tf = NULL;
        s = cli_demo_scene(dev, &sc->vol, &tf);
        lc_tf_destroy(tf);
        snprintf(sc->source, sizeof sc->source, "lanecast demo (tools/cli_particles.c)");
    } else if (rs || !strncmp(name, "file:", 5)) {
        char path[512] = "", comp[512] = "";
        if (rs) {
            snprintf(path, sizeof path, "%s/%s", data_dir, rs->path);
            if (rs->companion) snprintf(comp, sizeof comp, "%s/%s", data_dir, rs->companion);
        } else snprintf(path, sizeof path, "%s", name + 5);
        FILE *f = fopen(path, "rb");
        if (!f) {
            snprintf(note, note_size, "scene %s skipped: %s is absent", name, path);
            sc->absent = 1;
            return LC_ERROR_IO;
        }
        fclose(f);
        snprintf(sc->source, sizeof sc->source, "%s%s%s", path, comp[0] ? " + " : "", comp);
        lc_load_desc ld = {.companion = comp[0] ? comp : NULL};
        s = lc_volume_load(dev, path, &ld, &sc->vol);
    } else {
        snprintf(note, note_size, "unknown scene '%s'", name);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    if (s != LC_OK) {
        /* the generators fail before any lanecast call only for lack of memory */
        if (!sc->vol && s == LC_ERROR_OUT_OF_MEMORY && p >= 0)
            snprintf(note, note_size, "scene %s: out of memory generating %.0f %s", name, n, p == P_GRID ? "^3 voxels" : "items");
        else snprintf(note, note_size, "scene %s: %s", name, lc_last_error());
        return s;
    }
    sc->gen_seconds = bench_now() - t0;
    fill_info(sc);
    sc->gen_seconds -= sc->build_seconds;
    return LC_OK;
}

void bench_scene_free(bench_scene *sc)
{
    lc_volume_destroy(sc->vol);
    sc->vol = NULL;
}

int bench_view_camera(const bench_scene *sc, const char *view, lc_camera *cam)
{
    float scale = !strcmp(view, "far") ? 1.0f : !strcmp(view, "medium") ? 0.55f : !strcmp(view, "close") ? 0.3f : 0;
    if (scale == 0) return -1;
    *cam = (lc_camera){.fovy = 40.0f};
    if (lc_camera_frame(&sc->info.bounds, LC_CAMERA_AZIMUTH, LC_CAMERA_ELEVATION, cam) != LC_OK) return -1;
    cam->eye.x = cam->at.x + scale * (cam->eye.x - cam->at.x);
    cam->eye.y = cam->at.y + scale * (cam->eye.y - cam->at.y);
    cam->eye.z = cam->at.z + scale * (cam->eye.z - cam->at.z);
    return 0;
}
