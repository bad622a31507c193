/* The compositing of host/mpi/mpi.c on its own (lanecast bench --mpi and
 * bench/mpi_composite.sh measure it on synthetic images). Needs MPI. */
#ifndef LC_HOST_MPI_INTERNAL_H
#define LC_HOST_MPI_INTERNAL_H

#include <mpi.h>
#include <string.h>
#include "host/mpi/dp.h"
#include "lanecast/lanecast_mpi.h"

/* What one rank's compositing took, step by step (fold, swap rounds, gather). */
typedef struct lci_mpi_cstats {
    int nsteps;
    double seconds[LCI_CSTEPS_MAX + 1]; /* the step: pack, message, blend (gather: receives and copies) */
    uint64_t bytes[LCI_CSTEPS_MAX + 1]; /* sent in the step */
    uint64_t pixels[LCI_CSTEPS_MAX + 1]; /* received and blended (gather: copied) */
    double total_seconds;               /* swap, gather and their agreements */
    uint64_t bytes_sent, messages_sent;
} lci_mpi_cstats;

/* Composites img (this rank's region image, w x h, its rect set) over comm
 * in the visibility order `order` (position -> rank) by the schedule of
 * composite.c; rank root gets the w x h RGBA result in rgba. Collective.
 * cs may be NULL. */
lc_status lci_mpi_composite(lc_device *dev, MPI_Comm comm, int root, int op, lci_cimage *img, const int *order,
                            float *rgba, lci_mpi_cstats *cs);

/* The chain (host/mpi/chain.c): desc (dvr) rendered by regions of t, the
 * image handed from rank to rank in visibility order `order` (pos_of: its
 * inverse) in `bands` bands of rows; rank root gets it in rgba. Fills st's
 * render and message fields. Collective. */
lc_status lci_mpi_chain(lc_device *dev, MPI_Comm comm, int root, const lc_render_desc *d, const lci_kdtree *t,
                        const int *order, const int *pos_of, int bands, float *rgba, lc_mpi_stats *st);

/* lc_mpi_volume_load of a particle file (host/mpi/mpi_pload.c): this
 * rank's part (dp.h "Particle parts"). Collective. */
lc_status lci_mpi_load_particles(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld,
                                 const char *format, float dt, lc_volume **out);
/* lc_mpi_volume_load of an RBF file (host/mpi/mpi_rload.c). Collective. */
lc_status lci_mpi_load_rbf(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld, float dt,
                           lc_volume **out);
/* Sends each of the n items (*items: nf floats each, x y z first; freed
 * here once packed, *items = NULL) to every rank whose region's cell the
 * cube of half side reach[i] around it meets (tree t); *recv (malloc'ed)
 * gets the *nrecv items sent to this rank, by sending rank in order.
 * Collective. */
lc_status lci_mpi_exchange(lc_device *dev, MPI_Comm comm, const lci_kdtree *t, size_t n, float **items, int nf,
                           const float *reach, float **recv, size_t *nrecv);

/* The parts' canonical_order (lc_particles_desc, lc_rbf_desc): 1, or -1
 * (Embree's build) when the load options set canonical_order = 0. With 1 a
 * part sums each sample in the whole set's order (docs/mpi.md "Bit for
 * bit"). */
static inline int lci_mpi_canonical(const lc_load_desc *ld)
{
    int on = 1;
    for (int i = 0; i < ld->noptions; i++)
        if (ld->options[i].key && ld->options[i].value && !strcmp(ld->options[i].key, "canonical_order"))
            on = strcmp(ld->options[i].value, "0") != 0;
    return on ? 1 : -1;
}

/* The peers of a kd-tree build over comm (mpi_pload.c): the sums and the
 * agreement before them by MPI_Allreduce; *p filled and returned. */
const lci_kd_peers *lci_mpi_kd_peers(MPI_Comm *comm, lci_kd_peers *p);

#endif
