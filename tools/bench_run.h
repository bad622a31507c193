/* lanecast bench: one case group over several targets (bench_run.c). */
#ifndef LC_BENCH_RUN_H
#define LC_BENCH_RUN_H

#include "bench_common.h"

#define BENCH_MAX_ROUNDS 256

typedef struct bench_group {
    const bench_scene *scene;
    const char *view, *mode_name, *method_name, *shading_name, *study;
    int width, height, packet, threads, cpus;
    float alpha_stop, sigma;   /* 0 = the library's default */
    int ntargets;
    lc_target targets[LC_TARGET_COUNT];
    lc_device *devs[LC_TARGET_COUNT];
    lc_device *scalar_dev;     /* the check's reference (same thread count) */
    int check_size;            /* 0 = no check */
    int warmup, min_rounds, max_rounds;
    double seconds;            /* time bound of the timed rounds */
    const bench_roof *roof;
    const char *machine;
    FILE *out;
} bench_group;

/* Checks and times the group, writes one record per target. Returns the
 * number of targets whose check failed or whose render failed. */
int bench_run_group(const bench_group *g, const lc_render_desc *d);
/* --jobs: full and navigation frames, a job's passes and `trials` cancel
 * latencies per target (bench_job.c), one "job" record each. Returns the
 * number of targets that failed. */
int bench_job_group(const bench_group *g, const lc_render_desc *d, int trials);
/* --baseline: this build's bench and the baseline's on the same case flags
 * (args) in `rounds` interleaved rounds; one "ab" record per case to out
 * (bench_ab.c). 0 ok, 1 when a run failed or no case was paired. */
int bench_ab(const char *baseline, int rounds, char **args, int nargs, FILE *out);
/* --profile: the grid stage profile of the group on the targets whose
 * variants are built (bench_profile.c), one "profile" record each. Returns
 * the number that failed. */
int bench_profile_group(const bench_group *g, const lc_render_desc *d);
/* the targets --profile's variants are built for, space-separated */
const char *bench_profile_targets(void);
/* --resample N,...: the exact frame, then per N the deposition to N^3 nodes,
 * the grid's frame and its PSNR against the exact one (bench_resample.c), one
 * "resample" record per target and N. Returns the number that failed. */
int bench_resample_group(const bench_group *g, const lc_render_desc *d, const int *sizes, int nsizes);
/* --read FILE: a trajectory's reading rates (bench_read.c), one "read"
 * record; 0 ok, 1 a read failed, 2 not a trajectory it times. */
int bench_read(const char *path, int rounds, FILE *out);

/* --composite (under mpiexec), --blend, --imbalance (bench_mpi.c): 0, or 1
 * after a message. */
int bench_composite(int rounds, const char *sizes, FILE *out);
int bench_blend(int rounds, FILE *out);
int bench_imbalance(int nscenes, char **scenes, const char *data_dir, FILE *out);

#endif
