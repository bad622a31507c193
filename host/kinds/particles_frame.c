/* How the coherent particle kernel runs a frame: the pass buffer, the group
 * and tile sides, and the environment knobs of tests and A/B runs (read by
 * the host, never by kernels; docs/DEVELOPERS.md). */
#include "host/internal.h"
#include "host/kinds/particles_frame.h"

/* LANECAST_PARTICLE_GROUP_LIST (tests and A/B runs): the coherent kernel's
 * group list capacity in entries, 0 for no lists (a BVH walk per pass);
 * unset or invalid: the kernel's default. */
static int32_t group_list_cap(void)
{
    long v = lci_env_long("LANECAST_PARTICLE_GROUP_LIST", 0, 1L << 24, -1);
    return v < 0 ? 0 : v == 0 ? -1 : (int32_t)v;
}

/* LANECAST_PARTICLE_EYE=0 (tests): the coherent kernel treats perspective
 * rays as if their origins differed (the arithmetic per lane, not once per
 * group); the image is the same, bit for bit. */
static int32_t eye_generic(void) { return lci_env_long("LANECAST_PARTICLE_EYE", 0, 1, 1) == 0; }

/* LANECAST_PARTICLE_CONE=0 (tests, A/B runs): list deposits test every
 * particle against each vector's rays without the per-vector cone pre-test
 * (particles_walk.h vcone_bits); the image is the same, bit for bit. */
int32_t lci_pcone_off(void) { return lci_env_long("LANECAST_PARTICLE_CONE", 0, 1, 1) == 0; }

/* LANECAST_PARTICLE_BUFFER_K (A/B runs): samples per ray per pass when the
 * render leaves buffer_samples at 0; unset or invalid: the default. */
static int32_t env_buffer_k(void) { return (int32_t)lci_env_long("LANECAST_PARTICLE_BUFFER_K", 1, 4096, 0); }

/* buffer_samples 0: the coherent kernel adapts its pass length per group
 * (particles_coherent.c pass_adapt) up to this many samples per ray and
 * field: 128 for one field, 128 / nf rounded down to a multiple of 8 (at least 8) for
 * more, so the buffer stays at most 128 rows. */
static int32_t buffer_capacity(int nf)
{
    int32_t k = (128 / (nf > 0 ? nf : 1)) & ~7;
    return k < 8 ? 8 : k;
}

void lci_pcoherent_settings(lc_kparticles *k, int nfields, int32_t buffer_samples)
{
    int32_t ek = env_buffer_k();
    k->buffer_adapt = buffer_samples == 0 && ek == 0;
    k->buffer_k = buffer_samples != 0 ? buffer_samples : ek ? ek : buffer_capacity(nfields);
    k->group_list_cap = group_list_cap();
    k->eye_generic = eye_generic();
    k->cone_off = lci_pcone_off();
}

/* Rays per coherent group side when the render leaves packet at its default
 * (0): 16x16 groups share one BVH walk per chunk among 4x the rays of 8x8
 * (commit ba96d7e, docs/bench/particles.md "Groups and tiles": 8-17% less CPU per close frame on
 * the benchmark sets, far frames within noise). With a perspective camera
 * and 16 lanes, 32x32 (commit 48c4dd2, the eye outside the particles' grown box:
 * with the kernel's cone pre-test and a list capacity that grows with the
 * group, 1e6 far 4-6% and 1tw7 far 1-3% less CPU, dense1e6 far within noise;
 * commit 2a05c66, the eye inside too: a 32x32 group fills its tile and keeps its
 * first pass length, 16 samples there (particles_coherent.c pass_first),
 * 1e6, 1tw7 and dense1e6 close 8-13% less CPU than 16x16 groups). The image
 * is the same whatever the side
 * (tests/test_particles_gsize.c). LANECAST_PARTICLE_GROUP=N (A/B runs, tests)
 * sets another side for every frame. */
#define GROUP_SIDE_DEFAULT 16
#define GROUP_SIDE_WIDE 32

int32_t lci_pgroup_side(const lc_render_desc *d, int lanes)
{
    if (d->packet != 0) return 0;
    long env = lci_env_long("LANECAST_PARTICLE_GROUP", 1, 64, 0);
    if (env > 0) return (int32_t)env;
    const lc_camera *c = &d->camera;
    /* 32x32 only where a group stays within 64 ray vectors (16 lanes): one list
       bit and one cone per vector; narrower targets would share bits and lose
       the culls (particles_walk.h vcull_on, vcone_on) */
    int wide = GROUP_SIDE_WIDE * GROUP_SIDE_WIDE <= 64 * lanes;
    return c->projection == LC_PERSPECTIVE && wide ? GROUP_SIDE_WIDE : GROUP_SIDE_DEFAULT;
}

/* Pixels per tile side when the render leaves tile at 0: 64 for wide groups
 * with the eye inside the particles' grown box (lc_kparticles_eye_inside), so
 * that a tile holds four 32x32 groups and the pass length adapts from group
 * to group (particles_coherent.c pass_adapt; a 32x32 group alone in a 32-pixel
 * tile keeps its first length). Commit 9befac8, avx512, 2 threads, CPU s, tile 32
 * -> 64, 2 interleaved runs: dense1e6 close 0.839-0.846 -> 0.780-0.792; 1e6 and 1tw7
 * close within noise; far views slower with 64 (dense1e6 0.447 -> 0.463, 1e6
 * 0.106 -> 0.117), so they keep 32. Adaptation stays within a tile, which
 * one worker runs in a fixed order: counters do not depend on scheduling. */
int lci_ptile_side(const lc_kframe *f, const lc_kparticles *k, int coherent)
{
    return coherent && k->group_side == GROUP_SIDE_WIDE && lc_kparticles_eye_inside(k, f) ? 64 : 0;
}
