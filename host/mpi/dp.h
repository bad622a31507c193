/* Data-parallel rendering without MPI (host/mpi/): the kd-tree partition of
 * the data into regions, their visibility order from the camera, and the
 * compositing schedule (binary swap with folding) over images held by
 * P ranks. host/mpi/mpi.c runs the schedule over MPI; tests run it over
 * virtual ranks in one process (lci_dp_composite_local). */
#ifndef LC_HOST_MPI_DP_H
#define LC_HOST_MPI_DP_H

#include <stddef.h>
#include <stdint.h>
#include "host/internal.h"
#include "kernels/shared/kframe.h"
#include "host/kinds/kind.h"
#include "host/api/render.h"

/* A kd-tree of nleaves regions over a box: node 0 is the root; a node with
 * leaf >= 0 is region `leaf`, else it splits at `split` on `axis` into
 * child[0] (x < split) and child[1] (x >= split). Each split value is this
 * one float; every region's cell copies it (lci_kd_cell). */
typedef struct lci_kd_node {
    int32_t axis, leaf;
    int32_t child[2];
    float split;
} lci_kd_node;

typedef struct lci_kdtree {
    int nleaves, nnodes;
    lci_kd_node *node;  /* 2 nleaves - 1 */
    lc_kregion *cell;   /* per region: its cell, faces outside the data at -+inf */
    lc_box3 *box;       /* per region: its cell clipped to the data's box */
    uint64_t *weight;   /* per region: the points (or voxels) it holds */
    int32_t *crange;    /* grids, per region: its cells c0[3], c1[3] (cells c0 .. c1 - 1); NULL for points */
} lci_kdtree;

/* Recursive bisection of `bounds` into nleaves regions (1 .. 65536), each
 * split on the box's longest axis where the weight on either side is in
 * proportion to the regions it gets: the n points (x, y, z arrays; n may be
 * 0) or, when x is NULL, voxels of a grid of `cells` cells per axis spread
 * uniformly (split planes on cell boundaries where the grid allows).
 * Deterministic: every rank building it from the same input gets the same
 * floats. */
lc_status lci_kd_build(lc_device *dev, const lc_box3 *bounds, int nleaves, size_t n, const float *x, const float *y,
                       const float *z, const int cells[3], lci_kdtree *out);
void lci_kd_release(lci_kdtree *t);
/* How the holders of a distributed build talk: sum(user, v, k) replaces k
 * counts by their sums over every holder (all call it alike); agree(dev,
 * user, s) returns every holder's status, the first failure's with its
 * message (lc_mpi_agree; NULL: s itself), taken before the first sum so a
 * holder that fails to allocate leaves none waiting in a sum. */
typedef struct lci_kd_peers {
    lc_status (*sum)(void *user, uint64_t *v, int n);
    lc_status (*agree)(lc_device *dev, void *user, lc_status s);
    void *user;
} lci_kd_peers;
/* The same tree when the n points are this holder's share of points spread
 * over several: each split is the same float lci_kd_build gives for all the
 * points together (dist_select in partition.c). */
lc_status lci_kd_build_dist(lc_device *dev, const lc_box3 *bounds, int nleaves, size_t n, const float *x,
                            const float *y, const float *z, const lci_kd_peers *peers, lci_kdtree *out);
/* Nonzero when the environment variable LANECAST_TEST_FAULT (a comma-separated
 * list) names `point`: the tests' way to make one rank fail at a step (an
 * allocation that fails) and see every rank stop with its message. */
int lci_test_fault(const char *point);
lc_status lci_kd_copy(lc_device *dev, const lci_kdtree *t, lci_kdtree *out);

/* The regions front to back as seen by the camera (SPEC.md "Regions"):
 * perspective from the eye (inside the data or a region too), orthographic
 * by the view direction. order[0 .. nleaves-1] gets region ids. */
void lci_kd_order(const lci_kdtree *t, const lc_kcamera *cam, int *order);

/* ---------------------------------------------------------------- compositing */

/* How images combine: dvr by "over" of premultiplied RGBA, the others by
 * the nearest depth (mip: minus the maximum, kernels/mode.h). */
enum { LCI_COMP_OVER = 0, LCI_COMP_DEPTH = 1 };

/* One rank's image: w x h premultiplied RGBA, depth (DEPTH only) and the
 * rectangle outside which it is empty (transparent, depth +inf): the
 * bounding rectangle of its non-empty pixels (lci_cimage_rect), so only
 * the pixels a region reaches are sent. */
typedef struct lci_cimage {
    int w, h;
    float *rgba;
    float *depth;
    int rect[4];
} lci_cimage;

/* Sets img->rect to the bounding rectangle of its non-empty pixels (of
 * rows [r0, r1) only). */
void lci_cimage_rect(lci_cimage *img, int op);
void lci_cimage_rect_rows(lci_cimage *img, int op, int r0, int r1);

/* One step of the schedule for the rank at visibility position pos of P:
 * SEND: send rows [y0, y1) to partner (then, for FOLD, stop); RECV_BLEND: receive
 * them from partner and composite (front: this rank's pixels are in front).
 * A swap round is a SEND and a RECV_BLEND with the same partner (halves
 * exchanged at once). */
typedef struct lci_cstep {
    int partner;    /* a visibility position */
    int send_y0, send_y1; /* rows sent (empty: none) */
    int recv_y0, recv_y1; /* rows received and blended (empty: none) */
    int front;      /* 1: this rank's pixels lie in front of the partner's */
} lci_cstep;

#define LCI_CSTEPS_MAX 20

/* The steps of visibility position pos of P ranks for an image of h rows,
 * and the rows [*own_y0, *own_y1) it holds composited at the end (empty for
 * ranks folded out). Returns the number of steps. */
int lci_cschedule(int P, int pos, int h, lci_cstep *steps, int *own_y0, int *own_y1);

/* Packs rows [y0, y1) of img inside its rect: a 4-int header (the rect of
 * what follows) and its pixels (RGBA, then depth for DEPTH). Returns the
 * floats written into buf (header included; buf holds at least
 * lci_cpack_max floats). */
size_t lci_cpack(const lci_cimage *img, int op, int y0, int y1, float *buf);
size_t lci_cpack_max(int w, int rows, int op);
/* Composites a packed buffer into img (front: img's pixels are in front) and
 * widens img's rect. */
void lci_cblend(lci_cimage *img, int op, const float *buf, int front);
/* The pixels a packed buffer holds. */
uint64_t lci_cpacked_pixels(const float *buf);
/* Rows [y0, y1) of the w-wide RGBA out from a packed buffer (transparent
 * outside its rect), or from an image's own rows. */
void lci_cunpack(const float *buf, int w, int y0, int y1, float *out);
void lci_cunpack_own(const lci_cimage *img, int y0, int y1, float *out);

/* The whole schedule over P images in one process, imgs[pos] in visibility
 * order; the result (rows of every owner gathered) into out (w x h RGBA,
 * and out_depth when not NULL). Counts bytes and messages per position
 * when bytes/msgs are not NULL. For tests and lci_dp_render_local. */
lc_status lci_dp_composite_local(lc_device *dev, int P, lci_cimage *imgs, int op, float *out, float *out_depth,
                                 uint64_t *bytes, uint64_t *msgs);

/* ---------------------------------------------------------------- regions of a render */

/* Checks that desc can render by regions (no opaque particle spheres, no
 * differential sampling: their samples are not the lattice's), then builds
 * the kd-tree of P regions over the volume's frame bounds, balanced by its
 * particle or RBF centres or its voxels. */
lc_status lci_dp_partition(lc_device *dev, const lc_render_desc *d, int P, lci_kdtree *t);
/* The compositing op of the desc's mode. */
int lci_dp_op(const lc_render_desc *d);
/* The kernel camera of the desc's frame (for lci_kd_order). */
lc_status lci_dp_camera(lc_device *dev, const lc_render_desc *d, lc_kcamera *cam);
/* Renders region `leaf` of t into img (w x h of the desc; its rgba, and
 * depth for LCI_COMP_DEPTH, allocated here; lci_cimage_free) and sets its
 * rect. */
lc_status lci_dp_render_region(lc_device *dev, const lc_render_desc *d, const lci_kdtree *t, int leaf,
                               lci_cimage *img, lc_render_stats *stats);
void lci_cimage_free(lci_cimage *img);
/* A whole data-parallel render in one process: P regions rendered one
 * after another, composited by the schedule (what P ranks compute).
 * rgba: w x h; stats (may be NULL): summed. region_samples (may be NULL):
 * P counts. */
lc_status lci_dp_render_local(lc_device *dev, const lc_render_desc *d, int P, float *rgba, lc_render_stats *stats,
                              uint64_t *region_samples);

/* The chain (dvr to the bit): region `leaf`'s pass, run on bands of rows
 * of an image that holds the (C, A) the regions in front of it left; the
 * rays go on from there (lc_ktile carry), so after the last region in
 * visibility order every pixel has had one process's operations in one
 * process's order. host/mpi/chain.c hands the bands from rank to rank. */
typedef struct lci_dp_chain {
    lci_pass pass;
    lc_tf *own_tf;
    lc_render_stats stats; /* summed over the bands run */
    int ready;
} lci_dp_chain;
lc_status lci_dp_chain_begin(lc_device *dev, const lc_render_desc *d, const lci_kdtree *t, int leaf, lci_dp_chain *c);
/* Rows [row0, row1) of rgba (w x h of the desc). */
lc_status lci_dp_chain_rows(lc_device *dev, lci_dp_chain *c, const lc_render_desc *d, float *rgba, int row0, int row1);
void lci_dp_chain_end(lci_dp_chain *c);
/* The first row of band b of `bands` (1 .. h) over h rows; b = bands gives h. */
int lci_dp_band_row(int h, int bands, int b);
/* lci_dp_render_local by the chain: band by band, the P regions in
 * visibility order on one image. */
lc_status lci_dp_render_chain(lc_device *dev, const lc_render_desc *d, int P, int bands, float *rgba,
                              lc_render_stats *stats, uint64_t *region_samples);

/* ---------------------------------------------------------------- partial grids (window.c) */

/* The nodes a rank holds of a grid: start .. start + count - 1 per axis (its
 * region's cells, ghost nodes around them, the start rounded down to a
 * multiple of 4), and the nodes own0 .. own1 - 1 it counts in histograms
 * (the regions' own ranges tile the grid). */
typedef struct lci_dp_window {
    int32_t start[3], count[3], own0[3], own1[3];
} lci_dp_window;

/* Ghost nodes beyond a region's cells for step dt (0: the grid's default). */
void lci_dp_grid_ghosts(const lc_grid_desc *g, float dt, int ghost[3]);
/* The kd-tree lci_dp_partition builds for the grid g describes (size,
 * spacing, origin; no data). */
lc_status lci_dp_grid_tree(lc_device *dev, const lc_grid_desc *g, int P, lci_kdtree *t);
void lci_dp_grid_window(const lci_kdtree *t, int leaf, const int32_t full[3], const int ghost[3], lci_dp_window *w);
/* tree, ghosts and window of region leaf of P in one call */
lc_status lci_dp_grid_plan(lc_device *dev, const lc_grid_desc *shape, int P, int leaf, float dt, lci_dp_window *w);
int lci_dp_window_covers(const lci_dp_window *have, const lci_dp_window *need);
/* Where a grid file's voxels lie (raw-volume, nrrd, metaimage, nifti of the
 * format registry's names); LC_ERROR_UNSUPPORTED (with a message) when the
 * file must be read whole (compressed or converted values, other formats). */
struct lci_vol_layout;
lc_status lci_dp_grid_layout(lc_device *dev, const char *path, const lc_load_desc *ld, const char *format,
                             struct lci_vol_layout *l);
/* The nodes start .. start + count - 1 of the file (x fastest, native byte
 * order, on the grid's axes), reading only their bytes; *out malloc'ed. */
lc_status lci_dp_grid_read(lc_device *dev, const char *path, const struct lci_vol_layout *l, const int32_t start[3],
                           const int32_t count[3], void **out);
/* The same nodes cut out of a whole grid's data (malloc'ed; NULL: out of memory). */
void *lci_dp_grid_cut(const lc_grid_desc *whole, const int32_t start[3], const int32_t count[3]);
/* The leaf brick ranges of the nodes held (lci_grid_bvh_ranges; malloc'ed). */
lc_status lci_dp_grid_ranges(lc_device *dev, const lc_grid_desc *shape, const lci_dp_window *w, const void *data,
                             float **bmin, float **bmax, size_t *nbricks);
/* The part's volume (lci_grid_create_window) from the whole grid's shape
 * (type, spacing, origin, brick, layout), the nodes held and the brick
 * ranges united over every part. */
lc_status lci_dp_grid_create(lc_device *dev, const lc_grid_desc *shape, const lci_dp_window *w, const void *data,
                             const float *bmin, const float *bmax, int P, int leaf,
                             lc_status (*reduce)(void *, uint64_t *, int), void *user, void (*user_free)(void *),
                             lc_volume **out);
/* A part of a grid renders only the region it was loaded for, and only when
 * it holds the nodes desc's step needs (LC_ERROR_INVALID_ARGUMENT else);
 * LC_OK for a whole grid or another kind. */
lc_status lci_dp_grid_check(lc_device *dev, const lc_render_desc *d, int P, int leaf);

/* ---------------------------------------------------------------- particle parts (pwindow.c) */

/* What a rank's part of a particle set keeps (lci_particles_part): the
 * kd-tree its load built over the whole set (the render's partition), its
 * region, and the reach its ghosts were chosen for: every particle whose
 * support grown by `reach_dt` (two steps: iso and pre-integration take the
 * sample before a region's first) in units of `support` radii reaches the
 * region's cell. */
typedef struct lci_dp_ppart {
    lci_kdtree tree;
    int parts, part;
    float support; /* sigma (Gaussian) or 1 (SPH kernels: H = r_i) */
    float dt;      /* the longest step the ghosts serve */
} lci_dp_ppart;

/* pp on the heap, its tree moved there (NULL: out of memory, the tree
 * released), and its free function (a part's part_free). */
lci_dp_ppart *lci_dp_ppart_keep(lc_device *dev, lci_dp_ppart *pp);
void lci_dp_ppart_free(void *pp);
/* The reach of a particle of radius r around its centre: its grown support
 * and two steps of dt. */
float lci_dp_reach(float support, float r, float dt);
/* Calls add(user, leaf) once for every region whose cell the cube of half
 * side reach around (x, y, z) meets (the owner among them). */
void lci_dp_regions_near(const lci_kdtree *t, float x, float y, float z, float reach, void (*add)(void *, int),
                         void *user);
/* The frame bounds of a particle set (host/kinds/particles.c's grown
 * bounds: the centres' box grown by support * the largest radius). */
lc_box3 lci_dp_particle_bounds(const lci_particles_global *g, float support);
/* Makes v (a particle volume of a part's particles: owners and ghosts,
 * nfields the whole set's) the whole set g to the frame, keeping pp (its
 * tree moves into v). */
lc_status lci_dp_particles_attach(lc_device *dev, lc_volume *v, const lci_particles_global *g, lci_dp_ppart *pp);
/* lc_particles_create of d, then lci_dp_particles_attach (pp's tree is
 * released on failure). */
lc_status lci_dp_particles_create(lc_device *dev, const lc_particles_desc *d, const lci_particles_global *g,
                                  lci_dp_ppart *pp, lc_volume **out);
/* The particles of whole whose reach meets region leaf's cell (reach scaled
 * by margin: 1 for rendering; tests pass less to see the image break), as a
 * desc over malloc'ed arrays (lci_dp_particles_free). For tests and rank 0
 * of a scatter in one process. */
lc_status lci_dp_particles_cut(lc_device *dev, const lc_particles_desc *whole, const lci_kdtree *t, int leaf,
                               float support, float dt, float margin, lc_particles_desc *out);
void lci_dp_particles_free(lc_particles_desc *d);
/* The part a particle or RBF volume is (NULL: a whole set, or a grid). */
const lci_dp_ppart *lci_dp_part_of(const lc_volume *v);
/* A particle or RBF part renders only its region of the partition it was
 * loaded for, with no larger support and no longer step than its ghosts
 * serve; LC_OK for a whole set or a grid. */
lc_status lci_dp_particles_check(lc_device *dev, const lc_render_desc *d, int P, int leaf);

#endif
