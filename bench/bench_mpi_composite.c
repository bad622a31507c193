/* The compositing of data-parallel rendering alone (host/mpi/mpi.c
 * lci_mpi_composite), under mpiexec -np P: every rank holds a random
 * premultiplied image covering the whole frame (the worst case: every pixel
 * is sent), composited in a random visibility order; per image size, the
 * median over reps of the slowest rank's time, each step's time, bytes and
 * pixels of the fastest run, and bytes and messages per rank against binary swap's
 * S (1 - 1/P), S = 16 W H. With --blend (one process): lci_cblend's
 * throughput. One JSON line per measurement on stdout (docs/BENCHMARKS.md
 * "Compositing"; bench/mpi_composite.sh runs it). With --imbalance FILE
 * [KEY=VALUE load options] (one process): each kd-tree region of
 * P = 2 .. 64 rendered in turn, the slowest against the mean render time.
 * usage: bench_mpi_composite [--reps N] [--sizes 1,64,256,...] | --blend |
 *        --imbalance FILE [KEY=VALUE ...] */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "host/mpi/mpi_internal.h"

static uint32_t seed = 1;
static float frand(void) { return (float)((seed = seed * 1664525u + 1013904223u) >> 8) / 16777216.0f; }

static void fill(lci_cimage *img, int w, int h)
{
    img->w = w, img->h = h, img->depth = NULL;
    img->rgba = malloc(sizeof(float) * 4 * (size_t)w * (size_t)h);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        float a = 0.1f + 0.8f * frand();
        float *c = img->rgba + 4 * i;
        c[0] = a * frand(), c[1] = a * frand(), c[2] = a * frand(), c[3] = a;
    }
    lci_cimage_rect(img, LCI_COMP_OVER);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* lci_cblend of a packed 1024^2 image into another, front and back. */
static int blend(void)
{
    enum { N = 1024 };
    lci_cimage a, b;
    fill(&a, N, N), fill(&b, N, N);
    float *buf = malloc(sizeof(float) * lci_cpack_max(N, N, LCI_COMP_OVER));
    lci_cpack(&b, LCI_COMP_OVER, 0, N, buf);
    for (int front = 0; front < 2; front++) {
        double best = 1e30;
        for (int r = 0; r < 15; r++) {
            double t0 = now();
            lci_cblend(&a, LCI_COMP_OVER, buf, front);
            double t = now() - t0;
            best = t < best ? t : best;
        }
        double px = (double)N * N;
        printf("{\"bench\": \"mpi_blend\", \"w\": %d, \"h\": %d, \"front\": %d, \"seconds\": %.6f, \"mpixels_per_s\": %.1f, "
               "\"gbytes_per_s\": %.2f}\n",
               N, N, front, best, px / best / 1e6, 48.0 * px / best / 1e9);
    }
    double best = 1e30;
    for (int r = 0; r < 15; r++) {
        double t0 = now();
        lci_cpack(&b, LCI_COMP_OVER, 0, N, buf);
        double t = now() - t0;
        best = t < best ? t : best;
    }
    printf("{\"bench\": \"mpi_pack\", \"w\": %d, \"h\": %d, \"seconds\": %.6f, \"gbytes_per_s\": %.2f}\n", N, N, best,
           32.0 * N * N / best / 1e9);
    free(buf), free(a.rgba), free(b.rgba);
    return 0;
}

/* Renders every region of P = 2 .. 64 of the scene in turn (256^2, the
 * default view and TF, 2 threads); max / mean region render time. */
static int imbalance(const char *name, int nopt, char **opts)
{
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    lc_option o[8];
    char kv[8][256];
    int n = 0;
    for (int i = 0; i < nopt && n < 8; i++) {
        snprintf(kv[n], sizeof kv[n], "%s", opts[i]);
        char *eq = strchr(kv[n], '=');
        if (!eq) continue;
        *eq = 0;
        o[n].key = kv[n], o[n].value = eq + 1, n++;
    }
    lc_load_desc ld = {.options = o, .noptions = n};
    struct { lc_volume *vol; lc_volume_info info; } sc;
    if (lc_volume_load(dev, name, &ld, &sc.vol) != LC_OK) {
        fprintf(stderr, "bench_mpi_composite: %s\n", lc_device_last_error(dev));
        return 1;
    }
    lc_volume_get_info(sc.vol, &sc.info);
    lc_tf *tf = NULL;
    lc_tf_auto(dev, sc.vol, NULL, 0.0f, &tf);
    lc_render_desc d = {0};
    d.width = d.height = 256, d.volume = sc.vol, d.tf = tf, d.alpha_stop = 1.0f;
    lc_camera_frame(&sc.info.bounds, 35.0f, 25.0f, &d.camera);
    for (int P = 2; P <= 64; P *= 2) {
        lci_kdtree t;
        if (lci_dp_partition(dev, &d, P, &t) != LC_OK) {
            fprintf(stderr, "bench_mpi_composite: %s\n", lc_device_last_error(dev));
            return 1;
        }
        double mx = 0.0, sum = 0.0;
        uint64_t wmin = UINT64_MAX, wmax = 0;
        for (int r = 0; r < P; r++) {
            lci_cimage img;
            double t0 = now();
            lci_dp_render_region(dev, &d, &t, r, &img, NULL);
            double dt = now() - t0;
            lci_cimage_free(&img);
            mx = dt > mx ? dt : mx, sum += dt;
            wmin = t.weight[r] < wmin ? t.weight[r] : wmin, wmax = t.weight[r] > wmax ? t.weight[r] : wmax;
        }
        printf("{\"bench\": \"mpi_imbalance\", \"scene\": \"%s\", \"regions\": %d, \"max_s\": %.4f, \"mean_s\": %.4f, "
               "\"imbalance\": %.3f, \"weight_min\": %llu, \"weight_max\": %llu}\n",
               name, P, mx, sum / P, mx / (sum / P), (unsigned long long)wmin, (unsigned long long)wmax);
        fflush(stdout);
        lci_kd_release(&t);
    }
    lc_tf_destroy(tf);
    lc_volume_destroy(sc.vol);
    lc_device_destroy(dev);
    return 0;
}

int main(int argc, char **argv)
{
    int reps = 15;
    const char *sizes = "1,64,128,256,512,1024,2048";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--blend")) return blend();
        if (!strcmp(argv[i], "--imbalance") && i + 1 < argc) return imbalance(argv[i + 1], argc - i - 2, argv + i + 2);
        if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) sizes = argv[++i];
        else {
            fprintf(stderr, "usage: bench_mpi_composite [--reps N] [--sizes 1,64,...] | --blend\n");
            return 2;
        }
    }
    int provided, rank, P;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &P);
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 1}, &dev);
    seed = 7u + 31u * (uint32_t)rank;
    int *order = malloc(sizeof(int) * (size_t)P);
    for (const char *p = sizes; *p;) {
        int n = atoi(p);
        while (*p && *p != ',') p++;
        if (*p == ',') p++;
        if (n < 1) continue;
        lci_cimage img;
        fill(&img, n, n);
        float *out = rank == 0 ? malloc(sizeof(float) * 4 * (size_t)n * (size_t)n) : NULL;
        double *tot = malloc(sizeof(double) * (size_t)reps);
        lci_mpi_cstats cs, keep;
        double best = 1e30;
        memset(&keep, 0, sizeof keep);
        for (int r = -2; r < reps; r++) { /* two warm-up runs */
            for (int q = 0; q < P; q++) order[q] = q;
            for (int q = P - 1; q > 0; q--) { /* the same random order on every rank */
                uint32_t s2 = (uint32_t)(r + 3) * 2654435761u + (uint32_t)q * 40503u;
                int j = (int)(s2 % (uint32_t)(q + 1)), t = order[q];
                order[q] = order[j], order[j] = t;
            }
            MPI_Barrier(MPI_COMM_WORLD);
            lci_mpi_composite(dev, MPI_COMM_WORLD, 0, LCI_COMP_OVER, &img, order, out, &cs);
            double mx = cs.total_seconds;
            MPI_Allreduce(&cs.total_seconds, &mx, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
            if (r >= 0) tot[r] = mx;
            if (r >= 0 && mx <= best) best = mx, keep = cs; /* the steps of the fastest run */
        }
        qsort(tot, (size_t)reps, sizeof *tot, cmp_double);
        /* bytes and messages of every rank; the fastest run's steps of rank 0 */
        uint64_t mine[2] = {keep.bytes_sent, keep.messages_sent}, *all = malloc(sizeof(uint64_t) * 2 * (size_t)P);
        MPI_Gather(mine, 2, MPI_UINT64_T, all, 2, MPI_UINT64_T, 0, MPI_COMM_WORLD);
        if (rank == 0) {
            double S = 16.0 * n * n, bound = S * (1.0 - 1.0 / P);
            printf("{\"bench\": \"mpi_composite\", \"ranks\": %d, \"w\": %d, \"h\": %d, \"reps\": %d, \"median_s\": %.6f, "
                   "\"min_s\": %.6f, \"swap_bound_bytes\": %.0f, \"steps_rank0\": [",
                   P, n, n, reps, tot[reps / 2], tot[0], bound);
            for (int i = 0; i < keep.nsteps; i++)
                printf("%s{\"s\": %.6f, \"bytes\": %llu, \"pixels\": %llu}", i ? ", " : "", keep.seconds[i],
                       (unsigned long long)keep.bytes[i], (unsigned long long)keep.pixels[i]);
            printf("], \"bytes_per_rank\": [");
            for (int q = 0; q < P; q++) printf("%s%llu", q ? ", " : "", (unsigned long long)all[2 * q]);
            printf("], \"messages_per_rank\": [");
            for (int q = 0; q < P; q++) printf("%s%llu", q ? ", " : "", (unsigned long long)all[2 * q + 1]);
            printf("]}\n");
            fflush(stdout);
        }
        free(all), free(tot), free(out), free(img.rgba);
    }
    free(order);
    lc_device_destroy(dev);
    MPI_Finalize();
    return 0;
}
