/* lanecast bench: the scenes (procedural with fixed seeds, or the shared
 * real data sets) and the three views. Everything goes through the public
 * API; a scene is built once and rendered by every target's device. */
#include <math.h>
#include <stdint.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdlib.h>
#include <string.h>
#include "bench_common.h"
#include "cli.h"

const char bench_scene_help[] =
    "      procedural particles (fixed seed, 1 particle per 8 cubic units; N up to 1e8):\n"
    "        uniform:N   radii uniform in [0.6, 1.2]\n"
    "        heavy:N     heavy-tailed radii: Pareto (alpha 2.5) from 0.4, capped at 12\n"
    "        cluster:N   dense: 16 Gaussian clusters (sd = side / 24), radii [0.3, 0.6]\n"
    "      procedural grids (N^3 nodes, N <= 1290):\n"
    "        grid:N      uint8 gyroid lattice in a sphere, air outside (/u16: values x 257 as uint16,\n"
    "                    /f32: values / 255 as float32)\n"
    "        blob:N      uint8 sum of 24 Gaussian blobs, mostly air\n"
    "      procedural RBF sets: rbf:N uniform, rbfc:N in 8 clusters\n"
    "      demo        the scene of lanecast demo (a two-field particle helix in a shell)\n"
    "      real data (DATA = --data; skipped with a note when absent):\n"
    "        1tii 1tw7 bigbox adk galaxy lcdm   (particles/)\n"
    "        engine neghip headsq hydrogen embryo headmr   (volumes/)\n"
    "      any file lanecast reads:  file:PATH\n"
    "      options after a scene, each /OPT (e.g. engine/bricked/brick:8, rbf:1e4/octree:16):\n"
    "        grids: /linear /bricked (voxel layout), /brick:L (BVH leaf side 1-16), /no-heuristics\n"
    "               (Knoll 2011 eqs. 5-7 off); RBF sets: /octree[:CELL_MAX] (the default method\n"
    "               renders Jang 2004's octree); particles: /builder:NAME (see --builders)\n";

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

/* The /OPT suffixes of a scene name (bench_scene_help). */
typedef struct scene_opts {
    char base[64];
    lc_grid_layout layout;
    int brick, no_heuristics, octree, cell_max;
    lc_value_type type; /* grid:N's value type: uint8 (0), /u16, /f32 */
    const char *builder; /* a name of bench_builders, or NULL */
} scene_opts;

const char *const bench_builders[] = {"embree", "sah", "canonical", NULL};

/* Splits name into its base and options; -1 with a message in note for an
 * unknown or malformed option. */
static int parse_opts(const char *name, scene_opts *o, char *note, size_t note_size)
{
    memset(o, 0, sizeof *o);
    const char *slash = strncmp(name, "file:", 5) ? strchr(name, '/') : NULL; /* a path keeps its slashes */
    size_t bl = slash ? (size_t)(slash - name) : strlen(name);
    if (bl >= sizeof o->base) bl = sizeof o->base - 1;
    memcpy(o->base, name, bl);
    o->base[bl] = 0;
    for (const char *p = slash; p && *p;) {
        const char *opt = p + 1, *next = strchr(opt, '/');
        size_t l = next ? (size_t)(next - opt) : strlen(opt);
        char v[64];
        snprintf(v, sizeof v, "%.*s", (int)(l < 63 ? l : 63), opt);
        char *end = NULL;
        long x = 0;
        if (!strcmp(v, "linear")) o->layout = LC_LAYOUT_LINEAR;
        else if (!strcmp(v, "bricked")) o->layout = LC_LAYOUT_BRICKED;
        else if (!strcmp(v, "no-heuristics")) o->no_heuristics = 1;
        else if (!strcmp(v, "u16")) o->type = LC_VALUE_UINT16;
        else if (!strcmp(v, "f32")) o->type = LC_VALUE_FLOAT32;
        else if (!strcmp(v, "octree")) o->octree = 1;
        else if (!strncmp(v, "brick:", 6) && (x = strtol(v + 6, &end, 10), !*end) && (x == 1 || x == 2 || x == 4 ||
                                                                                     x == 8 || x == 16))
            o->brick = (int)x;
        else if (!strncmp(v, "octree:", 7) && (x = strtol(v + 7, &end, 10), !*end) && x >= 1 && x <= LC_RBF_MAX_CELL)
            o->octree = 1, o->cell_max = (int)x;
        else if (!strncmp(v, "builder:", 8)) {
            for (int b = 0; bench_builders[b]; b++)
                if (!strcmp(v + 8, bench_builders[b])) o->builder = bench_builders[b];
            if (!o->builder) goto bad;
        } else {
        bad:
            if (note) snprintf(note, note_size, "scene %s: unknown option '/%s' (see lanecast bench --help)", name, v);
            return -1;
        }
        p = next;
    }
    return 0;
}

/* "kind:N" with N a count like 1e5; returns the kind prefix index or -1. */
static const char *const prefixes[] = {"uniform:", "heavy:", "cluster:", "grid:", "rbf:", "rbfc:", "blob:"};
enum { P_UNIFORM, P_HEAVY, P_CLUSTER, P_GRID, P_RBF, P_RBFC, P_BLOB, P_COUNT };

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

int bench_scene_known(const char *full)
{
    double n;
    scene_opts o;
    if (parse_opts(full, &o, NULL, 0)) return 0;
    const char *name = o.base;
    return find_real(name) || parse_proc(name, &n) >= 0 || (!strncmp(name, "file:", 5) && name[5]) ||
           !strcmp(name, "demo");
}

/* Memory of a build: VmHWM is reset (/proc/self/clear_refs "5") just before
 * the create or load call, so afterwards it is the process's peak during
 * the call; the build's peak is that minus VmRSS before (the caller's arrays,
 * the device), after malloc_trim has returned the free heap to the system. */
static long status_kb(const char *key)
{
    char line[256];
    long v = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, key, strlen(key))) v = strtol(line + strlen(key), NULL, 10);
    fclose(f);
    return v;
}

static double cpu_at_begin; /* CPU seconds of the process when the create call began */

static long peak_begin(void)
{
#ifdef __GLIBC__
    malloc_trim(0); /* freed memory of earlier scenes back to the system, so a build cannot reuse it unseen */
#endif
    cpu_at_begin = bench_cpu_now();
    FILE *f = fopen("/proc/self/clear_refs", "w");
    int ok = f && fputs("5", f) >= 0;
    if (f && fclose(f)) ok = 0;
    return ok ? status_kb("VmRSS:") : -1; /* -1: no reset, no peak */
}

static void peak_end(bench_scene *sc, long before)
{
    long hwm = status_kb("VmHWM:");
    sc->build_cpu_s = bench_cpu_now() - cpu_at_begin;
    sc->build_peak_kb = before >= 0 && hwm >= before ? hwm - before : -1;
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
    long before = peak_begin();
    lc_status s = lc_particles_create(dev, &(lc_particles_desc){.count = n, .positions = xyz, .radii = r}, &sc->vol);
    peak_end(sc, before);
    free(xyz);
    free(r);
    return s;
}

/* a gyroid lattice inside a sphere, air outside (deterministic); o->type
 * widens it to uint16 (x 257) or float32 (/ 255) */
static lc_status make_grid(lc_device *dev, int n, const scene_opts *o, bench_scene *sc)
{
    int u16 = o->type == LC_VALUE_UINT16, f32 = o->type == LC_VALUE_FLOAT32;
    size_t count = (size_t)n * n * n;
    uint8_t *v = malloc(count * (f32 ? 4 : u16 ? 2 : 1));
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
    if (u16) /* widen in place, from the end */
        for (size_t e = count; e-- > 0;) ((uint16_t *)(void *)v)[e] = (uint16_t)(v[e] * 257u);
    if (f32)
        for (size_t e = count; e-- > 0;) ((float *)(void *)v)[e] = (float)v[e] / 255.0f;
    snprintf(sc->source, sizeof sc->source, "procedural %s %d^3 gyroid in a sphere", u16 ? "uint16" : f32 ? "float32" : "uint8", n);
    long before = peak_begin();
    lc_grid_desc d = {.size = {n, n, n}, .type = u16 ? LC_VALUE_UINT16 : f32 ? LC_VALUE_FLOAT32 : LC_VALUE_UINT8,
                      .data = v, .layout = o->layout, .brick = o->brick};
    lc_status st = lc_grid_create(dev, &d, &sc->vol);
    peak_end(sc, before);
    free(v);
    return st;
}

/* a uint8 sum of 24 Gaussian blobs (centres, radii and weights from a fixed
 * LCG) scaled to 0..255; most of the cube is air */
static lc_status make_blobs(lc_device *dev, int n, const scene_opts *o, bench_scene *sc)
{
    enum { NB = 24 };
    float c[NB][3], r[NB], w[NB];
    uint32_t s = 12345u;
    for (int b = 0; b < NB; b++) {
        for (int a = 0; a < 3; a++) s = s * 1664525u + 1013904223u, c[b][a] = 0.2f + 0.6f * (float)(s >> 8) / 16777216.0f;
        s = s * 1664525u + 1013904223u, r[b] = 0.05f + 0.10f * (float)(s >> 8) / 16777216.0f;
        s = s * 1664525u + 1013904223u, w[b] = 0.5f + 0.5f * (float)(s >> 8) / 16777216.0f;
    }
    uint8_t *v = malloc((size_t)n * n * n);
    if (!v) return LC_ERROR_OUT_OF_MEMORY;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                float x = (float)i / (float)(n - 1), y = (float)j / (float)(n - 1), z = (float)k / (float)(n - 1), sum = 0;
                for (int b = 0; b < NB; b++) {
                    float dx = x - c[b][0], dy = y - c[b][1], dz = z - c[b][2];
                    float q = (dx * dx + dy * dy + dz * dz) / (r[b] * r[b]);
                    if (q < 9.0f) sum += w[b] * expf(-q);
                }
                v[((size_t)k * n + j) * n + i] = (uint8_t)(255.0f * fminf(sum, 1.0f) + 0.5f);
            }
    snprintf(sc->source, sizeof sc->source, "procedural uint8 %d^3 sum of 24 Gaussian blobs (LCG seed 12345)", n);
    long before = peak_begin();
    lc_grid_desc d = {.size = {n, n, n}, .type = LC_VALUE_UINT8, .data = v, .layout = o->layout, .brick = o->brick};
    lc_status st = lc_grid_create(dev, &d, &sc->vol);
    peak_end(sc, before);
    free(v);
    return st;
}

/* centres in [-1, 1]^3 or in 8 clusters (normal, sd 0.12), widths
 * 0.5 n^(-1/3) U(0.5, 1.5) (each point lies in a few supports in the uniform
 * sets, in many inside clusters), weights U(-0.5, 1), eps the default. */
static lc_status make_rbf(lc_device *dev, int clustered, size_t n, const scene_opts *o, bench_scene *sc)
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
    long before = peak_begin();
    lc_rbf_desc d = {.count = n, .centres = c, .widths = s, .weights = w, .accel = o->octree ? LC_RBF_ACCEL_OCTREE : 0,
                     .cell_max = o->cell_max};
    lc_status st = lc_rbf_create(dev, &d, &sc->vol);
    peak_end(sc, before);
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
        if (ri.accel == LC_RBF_ACCEL_OCTREE) {
            size_t l = strlen(sc->source);
            snprintf(sc->source + l, sizeof sc->source - l, "; octree cell_max %d: %d cells, %zu bytes, %.4g s",
                     ri.cell_max, ri.octree_cells, ri.octree_bytes, ri.octree_seconds);
        }
    }
}

/* The options that fit the scene's kind are applied; another is an error. */
static int check_opts(bench_scene *sc, const scene_opts *o, char *note, size_t note_size)
{
    const char *bad = sc->kind != LC_KIND_GRID && (o->layout || o->brick || o->no_heuristics || o->type) ? "grid"
                    : sc->kind != LC_KIND_RBF && o->octree                                   ? "RBF set"
                    : sc->kind != LC_KIND_PARTICLES && o->builder                            ? "particle set"
                                                                                             : NULL;
    if (bad) {
        snprintf(note, note_size, "scene %s: an option of a %s on a %s scene", sc->name, bad, lc_kind_name(sc->kind));
        return -1;
    }
    if (o->no_heuristics) lc_grid_set_params(sc->vol, &(lc_grid_params){.delta_c = -1, .delta_p = -1, .delta_sv = -1});
    return 0;
}

static lc_status make_base(lc_device *dev, const char *name, const scene_opts *o, const char *data_dir,
                           bench_scene *sc, char *note, size_t note_size);

lc_status bench_scene_make(lc_device *dev, const char *full, const char *data_dir, bench_scene *sc, char *note,
                           size_t note_size)
{
    memset(sc, 0, sizeof *sc);
    sc->build_peak_kb = -1;
    snprintf(sc->name, sizeof sc->name, "%s", full);
    scene_opts o;
    if (parse_opts(full, &o, note, note_size)) return LC_ERROR_INVALID_ARGUMENT;
    const char *name = o.base;
    /* the particle builder is chosen by LANECAST_PBVH_BUILDER (bvh/particle_bvh.c), read at the build */
    char *saved = getenv("LANECAST_PBVH_BUILDER") ? strdup(getenv("LANECAST_PBVH_BUILDER")) : NULL;
    if (o.builder) setenv("LANECAST_PBVH_BUILDER", o.builder, 1);
    lc_status s = make_base(dev, name, &o, data_dir, sc, note, note_size);
    if (o.builder) {
        if (saved) setenv("LANECAST_PBVH_BUILDER", saved, 1);
        else unsetenv("LANECAST_PBVH_BUILDER");
    }
    free(saved);
    if (s == LC_OK && check_opts(sc, &o, note, note_size)) {
        bench_scene_free(sc);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    return s;
}

static lc_status make_base(lc_device *dev, const char *name, const scene_opts *o, const char *data_dir,
                           bench_scene *sc, char *note, size_t note_size)
{
    double n = 0, t0 = bench_now();
    int p = parse_proc(name, &n);
    const real_set *rs = find_real(name);
    lc_status s;
    if (o->type && p != P_GRID) {
        snprintf(note, note_size, "scene %s: /u16 and /f32 are options of grid:N only", name);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    if (p >= 0 && p != P_GRID && p != P_BLOB && n > 1e8) { /* checked before allocating: 1e8 particles take ~5 GB with the BVH */
        snprintf(note, note_size, "scene %s: at most 1e8 particles or RBFs", name);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    if (p == P_UNIFORM || p == P_HEAVY || p == P_CLUSTER) s = make_particles(dev, p, (size_t)n, sc);
    else if (p == P_GRID || p == P_BLOB) {
        if (n < 2 || n > 1290) { /* 1290^3 < 2^31 values */
            snprintf(note, note_size, "scene %s: a grid side from 2 to 1290", name);
            return LC_ERROR_INVALID_ARGUMENT;
        }
        s = p == P_GRID ? make_grid(dev, (int)n, o, sc) : make_blobs(dev, (int)n, o, sc);
    } else if (p == P_RBF || p == P_RBFC) s = make_rbf(dev, p == P_RBFC, (size_t)n, o, sc);
    else if (!strcmp(name, "demo")) {
        lc_tf *tf = NULL;
        long before = peak_begin();
        s = cli_demo_scene(dev, &sc->vol, &tf);
        peak_end(sc, before);
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
        char bs[16], cs[16];
        snprintf(bs, sizeof bs, "%d", o->brick);
        snprintf(cs, sizeof cs, "%d", o->cell_max);
        lc_option opt[4];
        int no = 0;
        if (o->brick) opt[no++] = (lc_option){"brick", bs};
        if (o->layout) opt[no++] = (lc_option){"layout", o->layout == LC_LAYOUT_LINEAR ? "linear" : "bricked"};
        if (o->octree) opt[no++] = (lc_option){"accel", "octree"};
        if (o->cell_max) opt[no++] = (lc_option){"cell_max", cs};
        lc_load_desc ld = {.companion = comp[0] ? comp : NULL, .options = opt, .noptions = no};
        long before = peak_begin();
        s = lc_volume_load(dev, path, &ld, &sc->vol);
        peak_end(sc, before);
    } else {
        snprintf(note, note_size, "unknown scene '%s'", name);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    if (s != LC_OK) {
        /* the generators fail before any lanecast call only for lack of memory */
        if (!sc->vol && s == LC_ERROR_OUT_OF_MEMORY && p >= 0)
            snprintf(note, note_size, "scene %s: out of memory generating %.0f %s", name, n, p == P_GRID || p == P_BLOB ? "^3 voxels" : "items");
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
