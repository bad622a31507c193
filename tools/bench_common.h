/* lanecast bench: shared declarations of the benchmark's files
 * (cmd_bench.c: options and the case loop; bench_scenes.c: the scenes and
 * views; bench_roofline.c: this machine's ceilings; bench_record.c: the JSON
 * record and the machine description). */
#ifndef LC_BENCH_COMMON_H
#define LC_BENCH_COMMON_H

#include <stdio.h>
#include "lanecast/lanecast.h"

/* ---- a scene: one volume, built once and shared by every target's device */
typedef struct bench_scene {
    char name[64];       /* as given: "uniform:1e5", "grid:256", "1tii", ... */
    char source[512];    /* how it was made: generator and seed, or the file path */
    lc_volume *vol;
    lc_kind kind;
    size_t count;        /* particles, RBFs or voxels */
    double build_seconds, gen_seconds;
    size_t bvh_bytes, data_bytes;
    long build_peak_kb;  /* the create or load call's peak memory above what was resident before; -1 unknown */
    double build_cpu_s;  /* CPU seconds of the process (every thread) during that call */
    lc_volume_info info;
    float max_radius;    /* particles and RBF sets: largest radius or width */
    int absent;          /* set with a failure: a real data set's file is missing (a skip, not an error) */
} bench_scene;

/* Builds a scene by name on dev. Returns LC_OK, or an error with a message in
 * *note; sc->absent is set when a real data set's file is missing (the caller
 * skips it with the note). */
lc_status bench_scene_make(lc_device *dev, const char *name, const char *data_dir, bench_scene *sc, char *note,
                           size_t note_size);
void bench_scene_free(bench_scene *sc);
/* 1 when the name is a known scene spelling (for checking --scenes up front). */
int bench_scene_known(const char *name);
/* The help text's list of scene names. */
extern const char bench_scene_help[];
/* The particle BVH builders a scene's /builder:NAME picks (NULL-terminated). */
extern const char *const bench_builders[];

/* far: the whole data framed (lc_camera_frame); medium: 0.55 of that
 * distance; close: 0.3 of it (inside dense particle sets). */
int bench_view_camera(const bench_scene *sc, const char *view, lc_camera *cam);

/* ---- roofline: ceilings of this machine per target, per core */
typedef struct bench_roof {
    int measured;
    double fma_gflops[LC_TARGET_COUNT];   /* FP32 multiply-add peak, 1 thread (scalar, sse4: mul + add) */
    double gauss_per_s[LC_TARGET_COUNT];  /* Gaussians at independent points, polynomial exp, 1 thread */
    double gather_l1[LC_TARGET_COUNT];    /* floats per second: gathers (or scalar loads for scalar/sse4), 16 KiB table */
    double gather_mem[LC_TARGET_COUNT];   /* the same from a 16 MiB table */
    double scalar_l1, scalar_mem;         /* scalar loads at random indices, floats per second */
    /* the grids' ceiling: trilinear samples per second streamed along rays
       through the uint8 z-paired quad copy (the grid kernels' layout, kgrid.h
       pair_quads), no traversal, classification or blending; a volume that
       stays in cache (64^3) and one that does not (320^3) */
    double grid_cache[LC_TARGET_COUNT], grid_mem[LC_TARGET_COUNT];
} bench_roof;

/* Measures every supported target for about `seconds` per kernel. */
void bench_roof_measure(bench_roof *r, double seconds);
/* FMA peak of avx512 over avx2 (1: 512-bit FMAs issue at half rate or
 * split; 2: full-width FMA pipes); 0 when either is not measured. */
double bench_fma_width_ratio(const bench_roof *r);
/* Writes one JSON record per target to f (kind "roofline"). */
void bench_roof_print(FILE *f, const bench_roof *r, const char *machine_json);

/* ---- records */
/* The machine, build and commit as the inside of a JSON object (no braces):
 * "cpu": ..., "flags": ..., "commit": ..., "compiler": ..., ... */
const char *bench_machine_json(void);
/* Writes s as a JSON string (quotes included). */
void bench_json_str(FILE *f, const char *s);
double bench_now(void);
double bench_cpu_now(void); /* CPU seconds of the whole process (every thread) */
long bench_rss_peak_kb(void);
long bench_rss_now_kb(void);
double bench_loadavg(void);
/* The median of v[0..n-1] (sorts v; NAN for n < 1). */
double bench_median(double *v, int n);
/* ", \"key\": v" to f, null when v is not finite. */
void bench_jnum(FILE *f, const char *key, double v);

#endif
