/* The coherent particle kernel's group lists (issue 8, "one walk per group":
 * kernels/particles_coherent.c): a group walks the BVH once per window of
 * passes and deposits from the list of leaves it found, instead of walking
 * once per pass. On every compiled and supported target, for dvr (1 and 2
 * fields, diffuse and phong shading, opaque spheres, sigma and kappa changed
 * after the build, early termination), mip and iso:
 * - the image with lists (the default) is bit-identical to the walk per pass
 *   (LANECAST_PARTICLE_GROUP_LIST=0), to lists of capacity 1 (every chunk
 *   overflows and falls back to the walk per pass) and of capacity 24 (some
 *   chunks fit, some not), for 8x8 groups, lane-width packets and 16x16
 *   groups (on scalar 256 vectors: a list bit stands for 4);
 * - with the perspective camera, the default (slab differences and centre
 *   offsets from the eye once per group, and the interval culls of nodes
 *   per group and per vector) is bit-identical to the arithmetic
 *   per lane (LANECAST_PARTICLE_EYE=0), with lists and with the walk per
 *   pass (a group cull 3% too eager fails 433 checks, a vector cull 377);
 * - lists visit fewer BVH nodes than the walk per pass, and capacity 1 a
 *   number of its own (the paths really differ: an ignored capacity fails);
 * - coherent agrees with direct, and dvr and mip with the reference core
 *   (tests/ref), at SPEC.md's tolerances (2/255, 50 dB).
 * Small buffers (8 samples per pass) give many passes per ray, so chunks of
 * 2, 4, 8 and 16 passes all occur. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"
#include "pclusters.h"
#include "imgcmp.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

#define W 40
#define H 40
#define NCL 160 /* per cluster */
#define NBG 120
#define N (3 * NCL + NBG)
#define DT 0.06f

static float xyz[3 * N], rad[N], val[N];
static uint8_t fid[N];
static double dxyz[3 * N], drad[N], dval[N];
static int dfid[N];

static void make_data(void)
{
    static const float cc[3][3] = {{3, 3, 4}, {6.5f, 5.5f, 5}, {4, 6.5f, 6.5f}};
    pclusters_make(0x2545f4914f6cdd1dull, NCL, NBG, cc, 0.8f, 0.3f, 0.15f, xyz, rad, val, fid);
    for (int i = 0; i < N; i++) {
        for (int a = 0; a < 3; a++) dxyz[3 * i + a] = xyz[3 * i + a];
        drad[i] = rad[i], dval[i] = val[i], dfid[i] = fid[i];
    }
}

typedef struct gcase {
    const char *name;
    lc_mode mode;
    int nfields;
    lc_shading shading;
    float sigma, kappa, scale; /* set after the build; scale > 0: opaque spheres */
    float alpha_stop;
    float iso;
    int ref; /* compare with the reference core */
} gcase;

static const gcase cases[] = {
    {"dvr", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1},
    {"dvr_f2_diffuse", LC_MODE_DVR, 2, LC_SHADE_DIFFUSE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1},
    {"dvr_spheres", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 1.0f, 0.35f, 1.0f, 0.0f, 1},
    {"dvr_sigma_kappa_phong", LC_MODE_DVR, 2, LC_SHADE_PHONG, 2.6f, 1.7f, 0.0f, 1.0f, 0.0f, 1},
    {"dvr_alpha_stop", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 3.0f, 0.0f, 0.9f, 0.0f, 0},
    {"mip_f2", LC_MODE_MIP, 2, LC_SHADE_NONE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f, 1},
    {"iso", LC_MODE_ISO, 1, LC_SHADE_DIFFUSE, 2.0f, 1.0f, 0.0f, 1.0f, 0.6f, 0},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

static const float colr[] = {0.0f, 0.9f, 0.3f, 0.1f, 0.5f, 0.2f, 0.8f, 0.3f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float opa[] = {0.0f, 0.0f, 0.15f, 0.0f, 1.0f, 3.0f};
#define HI 3.0f

static const lc_camera cam = {LC_PERSPECTIVE, {5, 5, 20}, {5, 5, 5}, {0, 1, 0}, 42.0f, 0.0f};

/* cap: NULL = the default (lists), "0" = a walk per pass, "1", "24": tiny lists. */
static int render(lc_device *dev, lc_volume *p, const gcase *c, lc_method m, int packet, const char *cap, float *img,
                  lc_render_stats *st)
{
    lc_tf_field f[2] = {{colr, 3, opa, 3, 1, {0.0f, HI}}, {colr, 3, opa, 3, 1, {0.0f, HI}}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, f, c->nfields, &tf) != LC_OK) return -1;
    lc_particle_params pp = {.sigma = c->sigma, .kappa = c->kappa, .buffer_samples = 8, .sphere_scale = c->scale};
    if (lc_particles_set_params(p, &pp) != LC_OK) return lc_tf_destroy(tf), -1;
    if (cap) setenv("LANECAST_PARTICLE_GROUP_LIST", cap, 1);
    lc_render_desc d = {.width = W, .height = H, .camera = cam, .tf = tf, .volume = p, .mode = c->mode,
                        .iso = c->iso, .dt = DT, .alpha_stop = c->alpha_stop, .shading = c->shading, .method = m,
                        .packet = packet};
    lc_status s = lc_render(dev, &d, img, st);
    unsetenv("LANECAST_PARTICLE_GROUP_LIST");
    lc_tf_destroy(tf);
    if (s != LC_OK) printf("lc_render: %s\n", lc_last_error());
    return s == LC_OK ? 0 : -1;
}

/* The reference image of a dvr or mip case, as floats. */
static float *reference(const gcase *c)
{
    static double dcol[12], dopa[6];
    for (int i = 0; i < 12; i++) dcol[i] = colr[i];
    for (int i = 0; i < 6; i++) dopa[i] = opa[i];
    ref_particle_set set = {N, dxyz, drad, dval, c->nfields > 1 ? dfid : NULL, c->nfields, c->sigma, c->kappa};
    ref_tf tf[2] = {{0.0, HI, dcol, 3, dopa, 3}, {0.0, HI, dcol, 3, dopa, 3}};
    ref_sphere_set spheres = {&set, c->scale};
    ref_params q = {0};
    q.width = W, q.height = H;
    q.camera = (ref_camera){REF_PERSPECTIVE, {5, 5, 20}, {5, 5, 5}, {0, 1, 0}, 42.0, 0.0};
    q.mode = c->mode == LC_MODE_MIP ? REF_MODE_MIP : REF_MODE_DVR;
    q.tf = tf;
    q.dt = DT;
    q.alpha_stop = c->alpha_stop;
    q.shading = c->shading == LC_SHADE_PHONG ? REF_SHADE_PHONG : c->shading == LC_SHADE_DIFFUSE ? REF_SHADE_DIFFUSE
                                                                                                : REF_SHADE_NONE;
    if (c->scale > 0.0f) q.surface = ref_particles_spheres, q.surface_user = &spheres;
    double *out = malloc(sizeof(double) * 4 * W * H);
    float *f = malloc(sizeof(float) * 4 * W * H);
    ref_source src;
    if (!out || !f || ref_particles_source(&set, &src) != 0 || ref_render(&src, &q, out) != 0) {
        CHECK(0, "reference render of %s", c->name);
        free(out), free(f);
        return NULL;
    }
    double ma = 0.0;
    for (int i = 0; i < 4 * W * H; i++) f[i] = (float)out[i];
    for (int i = 0; i < W * H; i++) ma += out[4 * i + 3] / (W * H);
    /* not vacuous: the scene is visible */
    CHECK(ma > 0.05, "reference %s: mean A %.3f > 0.05", c->name, ma);
    free(out);
    return f;
}

static int same_bits(const float *a, const float *b) { return memcmp(a, b, sizeof(float) * 4 * W * H) == 0; }

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : ".";
    make_data();
    float *refs[NCASES] = {0};
    for (int ci = 0; ci < NCASES; ci++)
        if (cases[ci].ref) refs[ci] = reference(&cases[ci]);
    static float list[W * H * 4], walk[W * H * 4], other[W * H * 4];
    imgcmp_worst wref = IMGCMP_WORST_INIT, wdir = IMGCMP_WORST_INIT;
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip target %s: not compiled in or not supported here\n", tn);
            continue;
        }
        lc_device *dev = NULL;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) {
            CHECK(0, "lc_device_create(%s): %s", tn, lc_last_error());
            continue;
        }
        lc_volume *pv[2] = {NULL, NULL};
        for (int nf = 1; nf <= 2; nf++) {
            lc_particles_desc pd = {.count = N, .positions = xyz, .radii = rad, .values = val,
                                    .fields = nf > 1 ? fid : NULL, .nfields = nf};
            CHECK(lc_particles_create(dev, &pd, &pv[nf - 1]) == LC_OK, "lc_particles_create: %s", lc_last_error());
        }
        for (int ci = 0; ci < NCASES && pv[0] && pv[1]; ci++) {
            const gcase *c = &cases[ci];
            lc_volume *p = pv[c->nfields - 1];
            static const int packets[] = {8, 1, 16}; /* 16: 256 scalar vectors, several per list bit */
            for (int pi = 0; pi < 3; pi++) {
                const int packet = packets[pi];
                lc_render_stats sl, sw, s1;
                char label[160];
                if (render(dev, p, c, LC_METHOD_COHERENT, packet, NULL, list, &sl) ||
                    render(dev, p, c, LC_METHOD_COHERENT, packet, "0", walk, &sw)) {
                    CHECK(0, "%s %s packet %d: render failed", tn, c->name, packet);
                    continue;
                }
                CHECK(same_bits(list, walk), "%s %s packet %d: lists = walk per pass, bit for bit", tn, c->name,
                      packet);
                CHECK(sl.nodes < sw.nodes, "%s %s packet %d: lists visit fewer nodes (%llu < %llu)", tn, c->name,
                      packet, (unsigned long long)sl.nodes, (unsigned long long)sw.nodes);
                CHECK(sl.passes == sw.passes, "%s %s packet %d: same passes (%llu, %llu)", tn, c->name, packet,
                      (unsigned long long)sl.passes, (unsigned long long)sw.passes);
                if (render(dev, p, c, LC_METHOD_COHERENT, packet, "1", other, &s1) == 0) {
                    CHECK(same_bits(other, walk), "%s %s packet %d: overflowing lists (capacity 1) = walk per pass",
                          tn, c->name, packet);
                    /* its own path: list walks that stop at the second leaf, then a walk per pass */
                    CHECK(s1.nodes != sl.nodes && s1.nodes != sw.nodes,
                          "%s %s packet %d: capacity 1 takes its own path (nodes %llu, lists %llu, walk %llu)", tn,
                          c->name, packet, (unsigned long long)s1.nodes, (unsigned long long)sl.nodes,
                          (unsigned long long)sw.nodes);
                } else {
                    CHECK(0, "%s %s: render failed", tn, c->name);
                }
                /* perspective rays share the eye: the walk's slab and the list deposit's
                   offsets once per group (the default) = per lane, bit for bit */
                setenv("LANECAST_PARTICLE_EYE", "0", 1);
                if (render(dev, p, c, LC_METHOD_COHERENT, packet, NULL, other, NULL) == 0)
                    CHECK(same_bits(other, list), "%s %s packet %d: lists, eye per lane = eye once", tn, c->name,
                          packet);
                else
                    CHECK(0, "%s %s: render failed", tn, c->name);
                if (render(dev, p, c, LC_METHOD_COHERENT, packet, "0", other, NULL) == 0)
                    CHECK(same_bits(other, walk), "%s %s packet %d: walk per pass, eye per lane = eye once", tn,
                          c->name, packet);
                else
                    CHECK(0, "%s %s: render failed", tn, c->name);
                unsetenv("LANECAST_PARTICLE_EYE");
                if (render(dev, p, c, LC_METHOD_COHERENT, packet, "24", other, NULL) == 0)
                    CHECK(same_bits(other, walk), "%s %s packet %d: lists of capacity 24 = walk per pass", tn,
                          c->name, packet);
                else
                    CHECK(0, "%s %s: render failed", tn, c->name);
                imgcmp_result r;
                if (refs[ci]) {
                    snprintf(label, sizeof label, "group_%s_%s_p%d_vs_ref", tn, c->name, packet);
                    int bad = imgcmp_check_ex(label, list, refs[ci], W, H, 0.0, 0.0, outdir, 1, &r);
                    imgcmp_worst_add(&wref, &r);
                    CHECK(bad == 0, "%s: coherent (lists) = reference (max %.3g/255, PSNR %.1f dB)", label,
                          r.max_diff_255, r.psnr_db);
                }
                if (packet == 8) {
                    if (render(dev, p, c, LC_METHOD_DIRECT, 0, NULL, other, NULL)) {
                        CHECK(0, "%s %s direct: render failed", tn, c->name);
                        continue;
                    }
                    snprintf(label, sizeof label, "group_%s_%s_vs_direct", tn, c->name);
                    int bad = imgcmp_check_ex(label, list, other, W, H, 0.0, 0.0, outdir, 1, &r);
                    imgcmp_worst_add(&wdir, &r);
                    CHECK(bad == 0, "%s: coherent (lists) = direct (max %.3g/255, PSNR %.1f dB)", label,
                          r.max_diff_255, r.psnr_db);
                }
            }
        }
        lc_volume_destroy(pv[0]);
        lc_volume_destroy(pv[1]);
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    imgcmp_worst_print("coherent with lists vs reference", &wref);
    imgcmp_worst_print("coherent with lists vs direct", &wdir);
    for (int ci = 0; ci < NCASES; ci++) free(refs[ci]);
    return check_summary("test_particles_group");
}
