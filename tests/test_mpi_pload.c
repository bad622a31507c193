/* lc_mpi_volume_load of particle and RBF files under mpiexec -np K
 * (tests/meson.build runs K = 1..4; host/mpi/mpi_pload.c, mpi_rload.c):
 * each rank's part (in the canonical order, lc_mpi_volume_load's default)
 * renders, through lc_mpi_render, rank 0's lc_render of the whole file
 * loaded with canonical_order 1 (dp_check_image: mip, iso and slice to the
 * bit, dvr within the over's round-off 2e-5, as grids; four views) for a raw float32 file (read as rows per rank), an XYZ file
 * with radii by element (read by rank 0 and scattered), an RBF set and a
 * raw file of 2 particles (ranks owning none); every part reports the whole
 * set's bounds and value range; the region weights sum to the count and no
 * part holds every particle (K > 1); a part loaded for sigma 3 renders at
 * sigma 3 and refuses 4 on every rank; a raw file cut short fails on every
 * rank with the last rank's message. With canonical_order 0 for both (Embree's
 * builds), K > 1: some mip, iso or slice image differs in its bits. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "imgcmp.h"
#include "lanecast/lanecast_mpi.h"
#include "dp_scene.h"

enum { N = 1500, NR = 150, W = 32, H = 24 };
static int rank, nranks;
static char dir[64];

static uint32_t rng = 99u;
static float urand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

static const char *path_of(const char *name)
{
    static char p[4][128];
    static int i;
    i = (i + 1) % 4;
    snprintf(p[i], sizeof p[i], "%s/%s", dir, name);
    return p[i];
}

static void write_files(void)
{
    FILE *f = fopen(path_of("p.f32"), "wb"), *t = fopen(path_of("short.f32"), "wb");
    for (int i = 0; i < N; i++) {
        float x[3];
        for (int a = 0; a < 3; a++) x[a] = 1.6f * urand() * urand() - 0.8f;
        fwrite(x, 4, 3, f);
        if (i < N - 2) fwrite(x, 4, 3, t);
    }
    fclose(f), fclose(t);
    f = fopen(path_of("two.f32"), "wb");
    const float two[6] = {-0.3f, 0.1f, 0.0f, 0.4f, -0.2f, 0.1f};
    fwrite(two, 4, 6, f), fclose(f);
    f = fopen(path_of("m.xyz"), "w");
    fprintf(f, "300\nmolecule\n");
    for (int i = 0; i < 300; i++)
        fprintf(f, "%s %.4f %.4f %.4f\n", (const char *[]){"C", "N", "O", "S", "H"}[i % 5], 6 * urand() - 3,
                6 * urand() * urand() - 3, 6 * urand() - 3);
    fclose(f);
    f = fopen(path_of("s.rbf"), "w");
    fprintf(f, "lanecast-rbf 1\nbias 0\ncount %d\n", NR);
    for (int i = 0; i < NR; i++)
        fprintf(f, "%.5f %.5f %.5f %.4f %.4f\n", 2 * urand() * urand() - 1, 2 * urand() - 1, 2 * urand() - 1,
                0.05f + 0.1f * urand(), 1.5f * urand() - 0.4f);
    fclose(f);
}

/* Loads path both ways (canonical_order 1 or 0) and compares the images in
 * four modes and four views; canonical 0 only counts the mip, iso and slice
 * images whose bits differ (returned). */
static int compare_file(lc_device *dev, const char *label, const char *path, const lc_option *opt, int nopt,
                        uint64_t count, int canonical)
{
    lc_option o2[8];
    if (nopt) memcpy(o2, opt, sizeof *opt * (size_t)nopt);
    o2[nopt] = (lc_option){"canonical_order", canonical ? "1" : "0"};
    lc_load_desc ld = {.options = o2, .noptions = nopt + 1};
    int differ = 0;
    lc_volume *part = NULL, *whole = NULL;
    lc_status s = lc_mpi_volume_load(dev, MPI_COMM_WORLD, path, &ld, 0.0f, &part);
    CHECK(s == LC_OK, "rank %d %s: lc_mpi_volume_load: %s", rank, label, lc_device_last_error(dev));
    if (s != LC_OK) return 0;
    if (rank == 0 && lc_volume_load(dev, path, &ld, &whole) != LC_OK)
        CHECK(0, "%s: lc_volume_load: %s", label, lc_device_last_error(dev));
    lc_volume_info pi, wi;
    lc_volume_get_info(part, &pi);
    if (rank == 0 && whole) {
        lc_volume_get_info(whole, &wi);
        CHECK(!memcmp(&pi.bounds, &wi.bounds, sizeof wi.bounds) && pi.range[0] == wi.range[0] &&
                  pi.range[1] == wi.range[1] && pi.nfields == wi.nfields,
              "%s np %d: the part's bounds, range and fields are the whole set's", label, nranks);
    }
    static const float col[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.5f, 1.0f, 0.4f, 0.1f, 1.0f, 1.0f, 1.0f, 0.8f};
    static const float op[] = {0.0f, 0.0f, 0.2f, 1.0f, 1.0f, 4.0f};
    lc_tf_field tff[8];
    for (int i = 0; i < 8; i++) tff[i] = (lc_tf_field){col, 3, op, 3, 1, {pi.range[0], pi.range[1]}};
    lc_tf *tf = NULL;
    lc_tf_create(dev, tff, pi.nfields, &tf);
    int before = check_failures;
    uint64_t weight = 0;
    for (int m = 0; m < 4; m++)
        for (int vi = 0; vi < DP_NVIEWS; vi++) {
            lc_render_desc d = dp_desc(part, tf, (lc_mode)m, vi, 1.0f, W, H, 0.3f);
            d.dt = 0.0f; /* the default step the ghosts were loaded for */
            float *got = malloc(sizeof(float) * 4 * W * H), *want = malloc(sizeof(float) * 4 * W * H);
            lc_mpi_stats st;
            s = lc_mpi_render(dev, MPI_COMM_WORLD, 0, &d, got, &st);
            CHECK_QUIET(s == LC_OK, "rank %d %s: %s", rank, label, lc_device_last_error(dev));
            weight = st.region_weight;
            if (s == LC_OK && rank == 0 && whole) {
                char l2[128];
                snprintf(l2, sizeof l2, "%s-%s-%s-np%d", label, dp_mode_names[m], dp_view_names[vi], nranks);
                d.volume = whole;
                if (lc_render(dev, &d, want, NULL) != LC_OK) CHECK(0, "%s: lc_render: %s", l2, lc_device_last_error(dev));
                else if (canonical) dp_check_image(l2, got, want, &d);
                else differ += m != LC_MODE_DVR && memcmp(got, want, sizeof(float) * 4 * W * H) != 0;
            }
            free(got), free(want);
        }
    uint64_t sum = 0;
    MPI_Allreduce(&weight, &sum, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0 && canonical)
        CHECK(check_failures == before && sum == count,
              "%s np %d: parts render the whole set's image (mip, iso, slice to the bit, dvr within 2e-5; 4 views); "
              "region weights sum to %llu", label, nranks, (unsigned long long)sum);
    lc_tf_destroy(tf);
    lc_volume_destroy(part);
    lc_volume_destroy(whole);
    return differ;
}

int main(int argc, char **argv)
{
    int provided;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &nranks);
    if (rank == 0) {
        snprintf(dir, sizeof dir, "/tmp/lc_mpi_pload_XXXXXX");
        if (!mkdtemp(dir)) dir[0] = 0;
        else write_files();
    }
    MPI_Bcast(dir, sizeof dir, MPI_CHAR, 0, MPI_COMM_WORLD);
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 1}, &dev);
    char cnt[32];
    snprintf(cnt, sizeof cnt, "%d", N);
    lc_option raw[2] = {{"count", cnt}, {"radius", "0.05"}}, two[2] = {{"count", "2"}, {"radius", "0.2"}};
    compare_file(dev, "raw", path_of("p.f32"), raw, 2, N, 1);
    compare_file(dev, "xyz-scattered", path_of("m.xyz"), NULL, 0, 300, 1);
    compare_file(dev, "rbf", path_of("s.rbf"), NULL, 0, NR, 1);
    compare_file(dev, "two-particles", path_of("two.f32"), two, 2, 2, 1);
    int differ = compare_file(dev, "raw-embree", path_of("p.f32"), raw, 2, N, 0);
    differ += compare_file(dev, "rbf-embree", path_of("s.rbf"), NULL, 0, NR, 0);
    if (rank == 0 && nranks > 1)
        CHECK(differ > 0, "np %d, canonical_order 0: %d of 24 raw and RBF mip/iso/slice images differ in their bits "
              "(the checks above can fail)", nranks, differ);

    /* the part's share: no rank holds every particle */
    lc_load_desc ld = {.options = raw, .noptions = 2};
    lc_volume *v = NULL;
    lc_status s = lc_mpi_volume_load(dev, MPI_COMM_WORLD, path_of("p.f32"), &ld, 0.0f, &v);
    lc_particles_info info;
    if (s == LC_OK) lc_particles_get_info(v, &info);
    if (s == LC_OK && nranks > 1)
        CHECK(info.count < N, "rank %d: its part holds %zu of %d particles", rank, info.count, N);
    lc_volume_destroy(v);

    /* loaded for sigma 3: renders at 3, refuses 4 on every rank */
    lc_option s3[3] = {{"count", cnt}, {"radius", "0.05"}, {"sigma", "3"}};
    ld = (lc_load_desc){.options = s3, .noptions = 3};
    s = lc_mpi_volume_load(dev, MPI_COMM_WORLD, path_of("p.f32"), &ld, 0.0f, &v);
    CHECK(s == LC_OK, "rank %d: load with sigma 3: %s", rank, lc_device_last_error(dev));
    if (s == LC_OK) {
        lc_tf *tf = NULL;
        lc_tf_preset(dev, "heat", 1, 10.0f, &tf);
        float img[4 * 64];
        lc_render_desc d = {.width = 8, .height = 8, .volume = v, .tf = tf, .mode = LC_MODE_DVR, .alpha_stop = 1.0f};
        d.camera = dp_views[0];
        lc_particles_set_params(v, &(lc_particle_params){.sigma = 3.0f});
        s = lc_mpi_render(dev, MPI_COMM_WORLD, 0, &d, img, NULL);
        CHECK(s == LC_OK, "rank %d: sigma 3 renders: %s", rank, lc_device_last_error(dev));
        lc_particles_set_params(v, &(lc_particle_params){.sigma = 4.0f});
        s = lc_mpi_render(dev, MPI_COMM_WORLD, 0, &d, img, NULL);
        CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "support"),
              "rank %d: sigma 4 is refused: %s", rank, lc_device_last_error(dev));
        lc_tf_destroy(tf);
        lc_volume_destroy(v);
    }

    /* cut short: the last rank reads the end; every rank fails with its message */
    ld = (lc_load_desc){.options = raw, .noptions = 2};
    v = NULL;
    s = lc_mpi_volume_load(dev, MPI_COMM_WORLD, path_of("short.f32"), &ld, 0.0f, &v);
    char want[32];
    snprintf(want, sizeof want, "rank %d: ", nranks - 1);
    const char *e = lc_device_last_error(dev);
    int named = strstr(e, "truncated") && (rank == nranks - 1 || !strncmp(e, want, strlen(want)));
    CHECK(s == LC_ERROR_FORMAT && !v && named, "rank %d: a truncated file fails: %s", rank, e);

    lc_device_destroy(dev);
    int mine = check_failures, total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        const char *names[] = {"p.f32", "short.f32", "two.f32", "m.xyz", "s.rbf"};
        for (int i = 0; i < 5; i++) unlink(path_of(names[i]));
        rmdir(dir);
    }
    MPI_Finalize();
    if (rank == 0) printf("test_mpi_pload np %d: %s (%d failures over all ranks)\n", nranks, total ? "FAIL" : "PASS", total);
    return total ? 1 : 0;
}
