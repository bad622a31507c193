/* Trajectory reading rates (issue 29, docs/bench/traj.md): every frame of
 * an XTC or TRR file read in order through the format's reader (descriptor
 * only: no volume, no BVH), in atoms per second, and one frame in the
 * middle read alone (random access: headers of the frames before it, then
 * that frame's coordinates), and frame 0 read 200 times (decoding alone, no
 * headers to scan). Reading every frame in order scans k headers for frame
 * k (no index is kept between loads), so all_s grows with frames^2.
 * usage: bench_traj FILE [REPEATS] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "host/formats/format.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int read_frame(lc_device *dev, const lci_format *f, const char *path, int64_t k, size_t *natoms)
{
    lc_option r = {"radius", "1"};
    lc_load_desc d = {.frame = k, .options = &r, .noptions = 1};
    lci_read_args a = {path, &d, &r, 1, f->name};
    lci_loaded l = {0};
    if (f->read(dev, &a, &l) != LC_OK) return fprintf(stderr, "%s\n", lc_last_error()), -1;
    *natoms = ((const lc_particles_desc *)l.desc)->count;
    lci_loaded_free(&l);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) return fprintf(stderr, "usage: bench_traj FILE [REPEATS]\n"), 2;
    int reps = argc > 2 ? atoi(argv[2]) : 3;
    const char *path = argv[1];
    size_t n = strlen(path);
    const lci_format *f = n > 4 && !strcmp(path + n - 4, ".trr") ? &lci_format_trr : &lci_format_xtc;
    lc_device *dev;
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    int64_t frames = 0;
    double t0 = now();
    if (f->frames(dev, path, &frames) != LC_OK) return fprintf(stderr, "%s\n", lc_last_error()), 1;
    double tcount = now() - t0, best = 1e30, mid = 1e30, first = 1e30;
    size_t natoms = 0;
    for (int r = 0; r < reps; r++) {
        t0 = now();
        for (int64_t k = 0; k < frames; k++)
            if (read_frame(dev, f, path, k, &natoms)) return 1;
        double t = now() - t0;
        best = t < best ? t : best;
        t0 = now();
        if (read_frame(dev, f, path, frames / 2, &natoms)) return 1;
        t = now() - t0;
        mid = t < mid ? t : mid;
        t0 = now();
        for (int i = 0; i < 200; i++)
            if (read_frame(dev, f, path, 0, &natoms)) return 1;
        t = (now() - t0) / 200;
        first = t < first ? t : first;
    }
    printf("traj file=%s format=%s frames=%lld atoms=%zu count_s=%.4f all_s=%.3f frames_per_s=%.1f atoms_per_s=%.3g "
           "frame%lld_s=%.5f frame0_s=%.5f frame0_atoms_per_s=%.3g\n", path, f->name, (long long)frames, natoms, tcount,
           best, (double)frames / best, (double)frames * (double)natoms / best, (long long)(frames / 2), mid, first,
           (double)natoms / first);
    lc_device_destroy(dev);
    return 0;
}
