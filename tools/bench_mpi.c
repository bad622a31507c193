/* lanecast bench --composite / --blend / --imbalance: the parts of
 * data-parallel rendering (host/mpi/) measured alone (docs/mpi.md,
 * docs/BENCHMARKS.md "Compositing"; bench/mpi_composite.sh runs them).
 *
 * --composite, under mpiexec -np P: every rank holds a random premultiplied
 * image covering the whole frame (the worst case: every pixel is sent),
 * composited by lci_mpi_composite in a random visibility order; per image
 * size, the median over the rounds of the slowest rank's time, each step's
 * time, bytes and pixels of the fastest run, and bytes and messages per rank
 * against binary swap's S (1 - 1/P), S = 16 W H.
 * --blend (one process): lci_cblend's and lci_cpack's throughput.
 * --imbalance (one process): each kd-tree region of P = 2 .. 64 of every
 * scene rendered in turn (256^2, the default view and TF, 2 threads), the
 * slowest region against the mean.
 * One JSON line per measurement (rank 0 writes them). The benchmark looks
 * inside the library here (host/mpi/dp.h), as the public API only offers the
 * whole collective render. */
#include <stdlib.h>
#include <string.h>
#include "bench_run.h"
#include "host/mpi/dp.h"
#if LC_HAVE_MPI
#include "host/mpi/mpi_internal.h"
#endif

static uint32_t seed = 1;
static float frand(void) { return (float)((seed = seed * 1664525u + 1013904223u) >> 8) / 16777216.0f; }

static int fill(lci_cimage *img, int w, int h)
{
    img->w = w, img->h = h, img->depth = NULL;
    img->rgba = malloc(sizeof(float) * 4 * (size_t)w * (size_t)h);
    if (!img->rgba) return -1;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        float a = 0.1f + 0.8f * frand();
        float *c = img->rgba + 4 * i;
        c[0] = a * frand(), c[1] = a * frand(), c[2] = a * frand(), c[3] = a;
    }
    lci_cimage_rect(img, LCI_COMP_OVER);
    return 0;
}

int bench_blend(int rounds, FILE *out)
{
    enum { N = 1024 };
    lci_cimage a, b;
    float *buf = malloc(sizeof(float) * lci_cpack_max(N, N, LCI_COMP_OVER));
    if (!buf || fill(&a, N, N) || fill(&b, N, N)) {
        fprintf(stderr, "lanecast bench: --blend: out of memory\n");
        return 1;
    }
    lci_cpack(&b, LCI_COMP_OVER, 0, N, buf);
    const double px = (double)N * N;
    for (int front = 0; front < 2; front++) {
        double best = 1e30;
        for (int r = 0; r < rounds; r++) {
            double t0 = bench_now();
            lci_cblend(&a, LCI_COMP_OVER, buf, front);
            double t = bench_now() - t0;
            best = t < best ? t : best;
        }
        fprintf(out, "{\"bench\": \"mpi_blend\", \"w\": %d, \"h\": %d, \"front\": %d, \"seconds\": %.6f, "
                "\"mpixels_per_s\": %.1f, \"gbytes_per_s\": %.2f, %s}\n",
                N, N, front, best, px / best / 1e6, 48.0 * px / best / 1e9, bench_machine_json());
    }
    double best = 1e30;
    for (int r = 0; r < rounds; r++) {
        double t0 = bench_now();
        lci_cpack(&b, LCI_COMP_OVER, 0, N, buf);
        double t = bench_now() - t0;
        best = t < best ? t : best;
    }
    fprintf(out, "{\"bench\": \"mpi_pack\", \"w\": %d, \"h\": %d, \"seconds\": %.6f, \"gbytes_per_s\": %.2f, %s}\n", N, N,
            best, 32.0 * px / best / 1e9, bench_machine_json());
    free(buf), free(a.rgba), free(b.rgba);
    return 0;
}

/* One scene's regions for P = 2 .. 64. */
static int imbalance_scene(lc_device *dev, const char *name, const char *data_dir, FILE *out)
{
    bench_scene sc;
    char note[512] = "";
    if (bench_scene_make(dev, name, data_dir, &sc, note, sizeof note) != LC_OK) {
        fprintf(stderr, "lanecast bench: %s: %s\n", name, note);
        return sc.absent ? 0 : 1;
    }
    lc_tf *tf = NULL;
    int rc = 0;
    if (lc_tf_auto(dev, sc.vol, NULL, 0.0f, &tf) != LC_OK) rc = 1;
    lc_render_desc d = {0};
    d.width = d.height = 256, d.volume = sc.vol, d.tf = tf, d.alpha_stop = 1.0f;
    lc_camera_frame(&sc.info.bounds, 35.0f, 25.0f, &d.camera);
    for (int P = 2; P <= 64 && !rc; P *= 2) {
        lci_kdtree t;
        if (lci_dp_partition(dev, &d, P, &t) != LC_OK) {
            rc = 1;
            break;
        }
        double mx = 0.0, sum = 0.0;
        uint64_t wmin = UINT64_MAX, wmax = 0;
        for (int r = 0; r < P && !rc; r++) {
            lci_cimage img;
            double t0 = bench_now();
            if (lci_dp_render_region(dev, &d, &t, r, &img, NULL) != LC_OK) rc = 1;
            double dt = bench_now() - t0;
            if (!rc) lci_cimage_free(&img);
            mx = dt > mx ? dt : mx, sum += dt;
            wmin = t.weight[r] < wmin ? t.weight[r] : wmin, wmax = t.weight[r] > wmax ? t.weight[r] : wmax;
        }
        if (!rc) {
            fprintf(out, "{\"bench\": \"mpi_imbalance\", \"scene\": ");
            bench_json_str(out, name);
            fprintf(out, ", \"regions\": %d, \"max_s\": %.4f, \"mean_s\": %.4f, \"imbalance\": %.3f, \"weight_min\": %llu, "
                    "\"weight_max\": %llu, %s}\n", P, mx, sum / P, mx / (sum / P), (unsigned long long)wmin,
                    (unsigned long long)wmax, bench_machine_json());
            fflush(out);
        }
        lci_kd_release(&t);
    }
    if (rc) fprintf(stderr, "lanecast bench: --imbalance %s: %s\n", name, lc_device_last_error(dev));
    lc_tf_destroy(tf);
    bench_scene_free(&sc);
    return rc;
}

int bench_imbalance(int nscenes, char **scenes, const char *data_dir, FILE *out)
{
    lc_device *dev;
    if (lc_device_create(&(lc_device_desc){.threads = 2}, &dev) != LC_OK) {
        fprintf(stderr, "lanecast bench: %s\n", lc_last_error());
        return 1;
    }
    int rc = 0;
    for (int i = 0; i < nscenes; i++) rc |= imbalance_scene(dev, scenes[i], data_dir, out);
    lc_device_destroy(dev);
    return rc;
}

#if LC_HAVE_MPI
static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One image size: every round composited, the slowest rank's time kept. */
static int composite_size(lc_device *dev, int n, int rounds, int rank, int P, int *order, FILE *out)
{
    lci_cimage img;
    float *o = rank == 0 ? malloc(sizeof(float) * 4 * (size_t)n * (size_t)n) : NULL;
    double *tot = malloc(sizeof(double) * (size_t)rounds);
    uint64_t *all = malloc(sizeof(uint64_t) * 2 * (size_t)P);
    int bad = fill(&img, n, n) || (rank == 0 && !o) || !tot || !all, anybad = 0;
    MPI_Allreduce(&bad, &anybad, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (anybad) {
        if (rank == 0) fprintf(stderr, "lanecast bench: --composite: out of memory at %dx%d\n", n, n);
        free(o), free(tot), free(all), free(img.rgba);
        return 1;
    }
    lci_mpi_cstats cs, keep;
    double best = 1e30;
    memset(&keep, 0, sizeof keep);
    for (int r = -2; r < rounds; r++) { /* two warm-up runs */
        for (int q = 0; q < P; q++) order[q] = q;
        for (int q = P - 1; q > 0; q--) { /* the same random order on every rank */
            uint32_t s2 = (uint32_t)(r + 3) * 2654435761u + (uint32_t)q * 40503u;
            int j = (int)(s2 % (uint32_t)(q + 1)), t = order[q];
            order[q] = order[j], order[j] = t;
        }
        MPI_Barrier(MPI_COMM_WORLD);
        lci_mpi_composite(dev, MPI_COMM_WORLD, 0, LCI_COMP_OVER, &img, order, o, &cs);
        double mx = cs.total_seconds;
        MPI_Allreduce(&cs.total_seconds, &mx, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        if (r >= 0) tot[r] = mx;
        if (r >= 0 && mx <= best) best = mx, keep = cs; /* the steps of the fastest run */
    }
    qsort(tot, (size_t)rounds, sizeof *tot, cmp_double);
    /* bytes and messages of every rank; the fastest run's steps of rank 0 */
    uint64_t mine[2] = {keep.bytes_sent, keep.messages_sent};
    MPI_Gather(mine, 2, MPI_UINT64_T, all, 2, MPI_UINT64_T, 0, MPI_COMM_WORLD);
    if (rank == 0) {
        double S = 16.0 * n * n, bound = S * (1.0 - 1.0 / P);
        fprintf(out, "{\"bench\": \"mpi_composite\", \"ranks\": %d, \"w\": %d, \"h\": %d, \"reps\": %d, \"median_s\": %.6f, "
                "\"min_s\": %.6f, \"swap_bound_bytes\": %.0f, \"steps_rank0\": [", P, n, n, rounds, tot[rounds / 2], tot[0],
                bound);
        for (int i = 0; i < keep.nsteps; i++)
            fprintf(out, "%s{\"s\": %.6f, \"bytes\": %llu, \"pixels\": %llu}", i ? ", " : "", keep.seconds[i],
                    (unsigned long long)keep.bytes[i], (unsigned long long)keep.pixels[i]);
        fprintf(out, "], \"bytes_per_rank\": [");
        for (int q = 0; q < P; q++) fprintf(out, "%s%llu", q ? ", " : "", (unsigned long long)all[2 * q]);
        fprintf(out, "], \"messages_per_rank\": [");
        for (int q = 0; q < P; q++) fprintf(out, "%s%llu", q ? ", " : "", (unsigned long long)all[2 * q + 1]);
        fprintf(out, "], %s}\n", bench_machine_json());
        fflush(out);
    }
    free(all), free(tot), free(o), free(img.rgba);
    return 0;
}

int bench_composite(int rounds, const char *sizes, FILE *out)
{
    int inited = 0, provided, rank, P;
    MPI_Initialized(&inited);
    if (!inited) MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &P);
    lc_device *dev = NULL;
    int rc = lc_device_create(&(lc_device_desc){.threads = 1}, &dev) != LC_OK;
    int *order = malloc(sizeof(int) * (size_t)P);
    seed = 7u + 31u * (uint32_t)rank;
    for (const char *p = sizes; !rc && order && *p;) {
        int n = atoi(p);
        while (*p && *p != ',') p++;
        if (*p == ',') p++;
        rc = composite_size(dev, n, rounds, rank, P, order, out);
    }
    free(order);
    if (dev) lc_device_destroy(dev);
    if (rc) MPI_Abort(MPI_COMM_WORLD, 1); /* no rank waits for another that stopped */
    if (!inited) MPI_Finalize();
    return rc;
}
#else
int bench_composite(int rounds, const char *sizes, FILE *out)
{
    (void)rounds, (void)sizes, (void)out;
    fprintf(stderr, "lanecast bench: --composite needs lanecast built with MPI (Debian: libopenmpi-dev)\n");
    return 1;
}
#endif
