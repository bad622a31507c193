/* lanecast over MPI: data-parallel rendering with ordered compositing
 * (built with the meson feature `mpi`; link with lanecast and MPI).
 *
 * Every rank of a communicator holds the same volume (or, with ghosts, the
 * part of it near its region) and calls lc_mpi_render with the same desc.
 * The data's box is split into one kd-tree region per rank (balanced by
 * particle or RBF counts, or voxels); each rank integrates only the
 * samples of the global eye-anchored lattice inside its region (SPEC.md
 * "Regions"); the images are composited front to back in the kd-tree's
 * order from the eye (premultiplied float RGBA "over" for dvr, the nearest
 * depth for mip, iso and slice) by binary swap with folding, or for dvr by
 * the chain (lc_mpi_compositing), and rank `root` gets the image: the one a
 * single process renders, to the bit (by binary swap, dvr up to the float
 * round-off of the "over").
 *
 * lanecast never calls MPI_Init: the caller initialises MPI (MPI_THREAD_FUNNELED
 * is enough: only the calling thread talks MPI). The communicator is
 * duplicated for each call. Collective: every rank calls it, also ranks
 * without data; a rank that fails (a bad desc, out of memory) makes every
 * rank return that rank's status with its message ("rank R: ..."), never a
 * hang. */
#ifndef LANECAST_MPI_H
#define LANECAST_MPI_H

#include <mpi.h>
#include <stdint.h>
#include "lanecast/lanecast.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What one rank did in lc_mpi_render; the *_max / *_mean fields are over
 * all ranks (every rank gets them). */
typedef struct lc_mpi_stats {
    int rank, ranks;
    int region;              /* the kd-tree region this rank rendered (= rank) */
    uint64_t region_weight;  /* particles, RBF terms or voxels the region holds */
    double render_seconds;   /* its region's render */
    double composite_seconds; /* binary swap and the gather to root (the chain: its messages and waits) */
    uint64_t bytes_sent, messages_sent;
    int rounds;              /* compositing steps (fold, swap rounds, gather; the chain: its bands) */
    int chain;               /* 1: dvr went by the chain (LC_MPI_CHAIN), 0: by binary swap */
    double render_max, render_mean; /* over ranks; imbalance = render_max / render_mean */
    lc_render_stats render;  /* the region render's counters */
    char read[128];          /* how lc_mpi_volume_load read this rank's part (its window of the
                                file, its share of rows, or rank 0's whole read and why); "" for
                                a volume made otherwise */
} lc_mpi_stats;

/* How the regions' dvr images become one. */
typedef enum lc_mpi_compositing {
    LC_MPI_AUTO = 0,  /* the chain for dvr; mip, iso and slice by binary swap (exact for them) */
    LC_MPI_CHAIN = 1, /* dvr: the image goes from rank to rank in visibility order in bands of
                         rows and each rank's rays go on from the (C, A) the ranks in front of it
                         left: one process's image to the bit. Each rank sends the whole image
                         once; the chain fills in P - 1 band times */
    LC_MPI_SWAP = 2   /* each region's segments blended alone, then "over" by binary swap with
                         folding: S (1 - 1/P) bytes a rank, within the float round-off of the
                         "over" of one process's image (below 1e-5 per channel in the tests) */
} lc_mpi_compositing;

typedef struct lc_mpi_options {
    lc_mpi_compositing compositing;
    int bands; /* the chain's bands of rows; 0: max(16, 4 P); at most the image's height and 4096 */
} lc_mpi_options;

/* Renders desc (pixel_scale 0 or 1) data-parallel over comm; rgba (width *
 * height * 4 floats, premultiplied, as lc_render) is written on rank root
 * only and may be NULL elsewhere. opts may be NULL (LC_MPI_AUTO); every
 * rank passes the same. stats may be NULL. Opaque particle spheres and
 * grids' differential sampling leave the lattice and are refused
 * (LC_ERROR_UNSUPPORTED). */
LC_API lc_status lc_mpi_render_with(lc_device *device, MPI_Comm comm, int root, const lc_render_desc *desc,
                                    const lc_mpi_options *opts, float *rgba, lc_mpi_stats *stats);
/* lc_mpi_render_with(device, comm, root, desc, NULL, rgba, stats). */
LC_API lc_status lc_mpi_render(lc_device *device, MPI_Comm comm, int root, const lc_render_desc *desc, float *rgba,
                               lc_mpi_stats *stats);

/* Collective: loads the part of the file at path that this rank's region
 * of a render on comm needs (lc_volume_load's desc; dt: the render's step,
 * 0 = the default; a longer step later is refused by lc_mpi_render).
 * Grids: the region's nodes plus ghost nodes (its cells' stencils, one
 * more, and a step's reach), read from their bytes of the file alone for
 * raw, NRRD and MetaImage files without compression and NIfTI files of
 * uint8, int16, uint16 or float32 without scaling or compression; other
 * grid files are read whole by rank 0, which sends each rank its part
 * (HDF5 grids, and frames past the first of those files: read whole by
 * every rank). The
 * part is a grid volume that is the whole grid to the API (lc_grid_info,
 * bounds, value range, BVH) and renders only its region under
 * lc_mpi_render; lc_grid_histogram (and so lc_tf_auto) becomes collective
 * on comm and returns the whole grid's counts. Destroy it before
 * MPI_Finalize. Particles: raw float32 files are read as one share of rows
 * per rank, other formats by rank 0; the kd-tree is built over the shares
 * (balanced by count, the splits one process's), and each rank keeps the
 * particles whose support (sigma r_i, or H = r_i for SPH kernels; load
 * option `sigma` for another sigma than the default 2) grown by two steps
 * dt reaches its region: a particle volume with the whole set's bounds,
 * radii and value range, rendered only under lc_mpi_render (a larger sigma
 * or a longer step is refused). RBF sets: rank 0 reads the file, each rank
 * keeps the terms whose support R_i grown by two steps reaches its region
 * (the whole set's eps, domain and default range). Particle and RBF parts
 * build their BVH in the canonical order (the default; load option
 * canonical_order = 0 for Embree's): each sample then sums its terms as one
 * process does, so every mode's image is one process's bit for bit (dvr by
 * LC_MPI_CHAIN; by LC_MPI_SWAP within the compositing's round-off). */
LC_API lc_status lc_mpi_volume_load(lc_device *device, MPI_Comm comm, const char *path, const lc_load_desc *desc,
                                    float dt, lc_volume **out);

/* Collective: every rank of comm passes its status; all get LC_OK when all
 * passed LC_OK, else the lowest failing rank's status, with its message
 * prefixed "rank R: " on the other ranks (lc_device_last_error). For a
 * caller's own steps (loading a file) before lc_mpi_render. */
LC_API lc_status lc_mpi_agree(lc_device *device, MPI_Comm comm, lc_status status);

#ifdef __cplusplus
}
#endif

#endif
