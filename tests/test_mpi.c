/* lc_mpi_render under mpiexec -np K (tests/meson.build runs K = 1..4):
 * the root (rank 0, 1, ...) compares the composited image with its own
 * lc_render of the same desc: mip, iso and slice to the bit; dvr by the
 * chain to the bit (early termination on or off), by binary swap within
 * float round-off of the "over" (2e-5) and within 1 - alpha_stop with
 * 0.97; for particles, a grid and an RBF set, four views (outside, eye
 * inside, orthographic, along an axis); particles fewer than the ranks
 * (ranks with no data), 1x1 and 13x7 images; a bad desc on one rank makes
 * every rank fail with that rank's message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "imgcmp.h"
#include "lanecast/lanecast_mpi.h"
#include "dp_scene.h"
#include "modes_scene.h"

static int rank, nranks;

/* One render on MPI_COMM_WORLD against lc_render on the root. dvr twice:
 * by the chain (bands of the default count or 5; to the bit with
 * alpha_stop 1) and by binary swap (within the round-off of the "over"). */
static void compare(lc_device *dev, const char *kind, const lc_volume *v, const lc_tf *tf, lc_mode mode, int vi,
                    float alpha_stop, int w, int h, float iso)
{
    lc_render_desc d = dp_desc(v, tf, mode, vi, alpha_stop, w, h, iso);
    size_t np = (size_t)w * (size_t)h;
    int root = vi % nranks; /* the root first, last or inside the visibility order */
    float *got = rank == root ? malloc(sizeof(float) * 4 * np) : NULL, *want = malloc(sizeof(float) * 4 * np);
    for (int way = 0; way < (mode == LC_MODE_DVR ? 2 : 1); way++) {
        lc_mpi_options o = {way == 0 ? LC_MPI_AUTO : LC_MPI_SWAP, vi % 2 ? 0 : 5};
        char label[160];
        snprintf(label, sizeof label, "%s-%s-%s-a%g-np%d-%dx%d-%s", kind, dp_mode_names[mode], dp_view_names[vi],
                 (double)alpha_stop, nranks, w, h, way ? "swap" : "auto");
        lc_mpi_stats st;
        lc_status s = lc_mpi_render_with(dev, MPI_COMM_WORLD, root, &d, &o, got, &st);
        CHECK_QUIET(s == LC_OK, "%s: %s", label, lc_device_last_error(dev));
        CHECK_QUIET(s != LC_OK || st.chain == (mode == LC_MODE_DVR && way == 0), "%s: chain %d", label, st.chain);
        if (rank == root && s == LC_OK) {
            lc_render(dev, &d, want, NULL);
            if (st.chain) { /* with early termination too */
                double e = 0.0;
                for (size_t i = 0; i < 4 * np; i++) e = fmax(e, fabs((double)got[i] - (double)want[i]));
                CHECK_QUIET(!memcmp(got, want, sizeof(float) * 4 * np), "%s: not one process's bits (max |diff| %.3g)",
                            label, e);
            } else {
                dp_check_image(label, got, want, &d);
            }
        }
    }
    free(got), free(want);
}

/* Cancels from its third call on: after the chain's first bands. */
static int cancel_later(void *user)
{
    int *calls = user;
    return ++*calls > 2;
}

int main(int argc, char **argv)
{
    int provided;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &nranks);
    to_double(col0, dcol0, 12), to_double(col1, dcol1, 8), to_double(opa, dopa, 4);
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 1}, &dev);
    static scene sc;
    make_scene(&sc);
    lc_tf_field tff[2] = {{col0, 3, opa, 2, 1, {0.0f, 1.0f}}, {col1, 2, opa, 2, 1, {0.0f, 1.0f}}};
    lc_tf *tf2 = NULL, *tf1 = NULL;
    lc_tf_create(dev, tff, 2, &tf2);
    lc_tf_create(dev, tff, 1, &tf1);
    lc_volume *pv = NULL, *gv = NULL, *rv = NULL, *few = NULL;
    lc_particles_desc pd = {.count = NP, .positions = sc.pos, .radii = sc.rad, .fields = sc.field, .nfields = 2};
    lc_particles_desc fd = {.count = 2, .positions = sc.pos, .radii = sc.rad, .fields = sc.field, .nfields = 2};
    lc_grid_desc gd = {.size = {GX, GY, GZ}, .type = LC_VALUE_FLOAT32, .data = sc.grid,
                       .spacing = {0.25f, 0.25f, 0.25f}, .origin = {-2.0f, -1.5f, -1.25f}};
    lc_rbf_desc rd = {.count = NR, .centres = sc.rc, .widths = sc.rs, .weights = sc.rw, .bias = RBF_BIAS,
                      .eps = RBF_EPS, .domain = rbf_domain};
    CHECK(lc_particles_create(dev, &pd, &pv) == LC_OK && lc_grid_create(dev, &gd, &gv) == LC_OK &&
              lc_rbf_create(dev, &rd, &rv) == LC_OK && lc_particles_create(dev, &fd, &few) == LC_OK,
          "rank %d: volumes", rank);
    int before = check_failures;
    for (int m = 0; m < 4; m++)
        for (int vi = 0; vi < 4; vi++) {
            compare(dev, "particles", pv, tf2, (lc_mode)m, vi, 1.0f, 32, 24, 0.3f);
            compare(dev, "grid", gv, tf1, (lc_mode)m, vi, 1.0f, 32, 24, 0.45f);
            compare(dev, "rbf", rv, tf1, (lc_mode)m, vi, 1.0f, 32, 24, 0.3f);
        }
    if (rank == 0)
        CHECK(check_failures == before, "np %d: particles, grid, rbf x dvr/mip/iso/slice x 4 views (alpha_stop 1) = one process", nranks);
    before = check_failures;
    for (int vi = 0; vi < 4; vi++) {
        compare(dev, "grid", gv, tf1, LC_MODE_DVR, vi, 0.97f, 32, 24, 0.0f);
        compare(dev, "particles", pv, tf2, LC_MODE_DVR, vi, 0.97f, 32, 24, 0.0f);
        compare(dev, "few-particles", few, tf2, LC_MODE_DVR, vi, 1.0f, 32, 24, 0.0f);
        compare(dev, "grid", gv, tf1, LC_MODE_MIP, vi, 1.0f, 1, 1, 0.0f);
        compare(dev, "rbf", rv, tf1, LC_MODE_DVR, vi, 1.0f, 13, 7, 0.0f);
    }
    if (rank == 0)
        CHECK(check_failures == before, "np %d: alpha_stop 0.97; 2 particles (ranks without data); 1x1 and 13x7 images", nranks);
    /* a bad desc on the last rank: every rank fails, naming it */
    lc_render_desc bad = {.width = rank == nranks - 1 ? 0 : 8, .height = 8, .volume = gv, .tf = tf1};
    float img[4 * 64];
    lc_status s = lc_mpi_render(dev, MPI_COMM_WORLD, 0, &bad, img, NULL);
    char want[32];
    snprintf(want, sizeof want, "rank %d: ", nranks - 1);
    int named = rank == nranks - 1 ? strstr(lc_device_last_error(dev), "image size") != NULL
                                   : strncmp(lc_device_last_error(dev), want, strlen(want)) == 0;
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && named, "rank %d: a bad width on rank %d fails here too: %s", rank,
          nranks - 1, lc_device_last_error(dev));
    /* a cancel on one rank in the middle of the chain: every rank returns, none waits */
    for (int who = 0; who < nranks; who++) {
        lc_render_desc dc = dp_desc(gv, tf1, LC_MODE_DVR, 0, 1.0f, 32, 24, 0.0f);
        int calls = 0;
        dc.cancel = rank == who ? cancel_later : NULL, dc.cancel_user = &calls;
        float *cimg = malloc(sizeof(float) * 4 * 32 * 24);
        lc_mpi_options o = {LC_MPI_CHAIN, 6};
        s = lc_mpi_render_with(dev, MPI_COMM_WORLD, 0, &dc, &o, cimg, NULL);
        CHECK_QUIET(s == LC_CANCELLED, "rank %d: a cancel on rank %d in the chain gives LC_CANCELLED here too (%d): %s", rank,
                    who, (int)s, lc_device_last_error(dev));
        free(cimg);
    }
    if (rank == 0) CHECK(check_failures == before, "np %d: a cancel on any rank during the chain's bands ends every rank", nranks);
    /* a bad root is refused on every rank without a collective */
    s = lc_mpi_render(dev, MPI_COMM_WORLD, nranks, &bad, img, NULL);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT, "rank %d: root %d refused: %s", rank, nranks, lc_device_last_error(dev));
    lc_volume_destroy(pv), lc_volume_destroy(gv), lc_volume_destroy(rv), lc_volume_destroy(few);
    lc_tf_destroy(tf1), lc_tf_destroy(tf2);
    lc_device_destroy(dev);
    int mine = check_failures, total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    MPI_Finalize();
    if (rank == 0) printf("test_mpi np %d: %s (%d failures over all ranks)\n", nranks, total ? "FAIL" : "PASS", total);
    return total ? 1 : 0;
}
