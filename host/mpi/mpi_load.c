/* lc_mpi_volume_load (lanecast_mpi.h): each rank loads the part of a file
 * its region needs. Grids: the region's nodes and ghosts (window.c), read
 * from the file where its voxels are plain (raw, NRRD, MetaImage, NIfTI) or
 * by one hyperslab (HDF5 datasets), else read whole by rank 0 and cut into
 * every rank's part (frames past the first of other files: read whole by
 * every rank); the BVH's leaf
 * ranges are united by an allreduce, so every rank's tree is the whole
 * grid's, and histograms (lc_tf_auto) are summed over ranks. Particle and
 * RBF sets: mpi_pload.c and mpi_rload.c. Every step ends in an agreement
 * (lc_mpi_agree), so a rank that fails stops all with its message. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/format.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"
#include "host/mpi/dp.h"
#include "host/mpi/mpi_internal.h"
#include "lanecast/lanecast_mpi.h"

static lc_status sum_counts(void *user, uint64_t *counts, int n)
{
    MPI_Comm *c = user;
    if (MPI_Allreduce(MPI_IN_PLACE, counts, n, MPI_UINT64_T, MPI_SUM, *c) != MPI_SUCCESS) return LC_ERROR_INTERNAL;
    return LC_OK;
}

static void free_comm(void *user)
{
    MPI_Comm *c = user;
    int done = 0;
    MPI_Finalized(&done);
    if (!done) MPI_Comm_free(c);
    free(c);
}

/* The grid (kind) options of ld applied to shape; the rest must be the format's. */
static lc_status kind_options(lc_device *dev, const char *path, const lc_load_desc *ld, const char *format,
                              lc_grid_desc *shape)
{
    const char *fopts = "";
    lc_format_info fi;
    for (int i = 0; i < lc_format_count(); i++)
        if (lc_format_get(i, &fi) == LC_OK && !strcmp(fi.name, format)) fopts = fi.options;
    for (int i = 0; ld && i < ld->noptions; i++) {
        const lc_option *o = &ld->options[i];
        if (!o->key || !o->value) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: an option without key or value", path);
        if (!strcmp(o->key, "brick") || !strcmp(o->key, "layout")) {
            lc_status s = lci_grid_ops.set_option(dev, shape, o, path);
            if (s != LC_OK) return s;
            continue;
        }
        size_t k = strlen(o->key);
        const char *p = strstr(fopts, o->key);
        int listed = 0;
        for (; p; p = strstr(p + 1, o->key))
            listed |= (p == fopts || p[-1] == ' ') && (p[k] == 0 || p[k] == ' ');
        if (!listed && strcmp(o->key, "max_memory"))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option '%s' does not apply to %s files (they take: %s)",
                             path, o->key, format, fopts);
    }
    return LC_OK;
}

/* The kind the registry gives the format (LC_KIND_NONE: the file decides, as HDF5's). */
static lc_kind format_kind(const char *format)
{
    lc_format_info fi;
    for (int i = 0; i < lc_format_count(); i++)
        if (lc_format_get(i, &fi) == LC_OK && !strcmp(fi.name, format)) return fi.kind;
    return LC_KIND_NONE;
}

/* The format's options alone (lci_read_grid refuses the kind's). */
static lc_load_desc format_only(const lc_load_desc *ld, lc_option *keep)
{
    lc_load_desc f = *ld;
    f.noptions = 0;
    for (int i = 0; i < ld->noptions; i++)
        if (strcmp(ld->options[i].key, "brick") && strcmp(ld->options[i].key, "layout")) keep[f.noptions++] = ld->options[i];
    f.options = keep;
    return f;
}

/* Rank 0 reads the whole grid and sends every rank its part: *shape and
 * *data (this rank's nodes of window w, planned here) on every rank. */
static lc_status scatter_grid(lc_device *dev, MPI_Comm comm, int rank, int P, const char *path, const lc_load_desc *ld,
                              float dt, lc_grid_desc *shape, lci_dp_window *w, void **data)
{
    lci_loaded whole;
    memset(&whole, 0, sizeof whole);
    lc_status s = LC_OK;
    struct { lc_grid_desc d; int ok; } head;
    memset(&head, 0, sizeof head);
    if (rank == 0) {
        lc_option *keep = malloc(sizeof *keep * (size_t)(ld->noptions + 1));
        const char *fmt = NULL;
        if (!keep) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        if (s == LC_OK) {
            lc_load_desc f = format_only(ld, keep);
            s = lci_read_grid(dev, path, &f, &fmt, &whole);
        }
        free(keep);
        if (s == LC_OK) {
            head.d = *(const lc_grid_desc *)whole.desc;
            head.d.data = NULL;
            head.d.brick = shape->brick, head.d.layout = shape->layout;
            head.ok = 1;
        }
    }
    lc_status agreed = lc_mpi_agree(dev, comm, s);
    if (agreed != LC_OK) {
        lci_loaded_free(&whole);
        return agreed;
    }
    MPI_Bcast(&head, (int)sizeof head, MPI_BYTE, 0, comm);
    *shape = head.d;
    s = lci_dp_grid_plan(dev, shape, P, rank, dt, w);
    int es = lci_value_size(shape->type);
    size_t bytes = s == LC_OK ? (size_t)w->count[0] * (size_t)w->count[1] * (size_t)w->count[2] * (size_t)es : 0;
    if (s == LC_OK && rank != 0 && (!(*data = malloc(bytes + 1)) || lci_test_fault("scatter")))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for a part of %zu bytes", path, bytes);
    s = lc_mpi_agree(dev, comm, s); /* every receiver waits for its part, with room for it */
    if (s != LC_OK) {
        lci_loaded_free(&whole);
        free(*data), *data = NULL;
        return s;
    }
    /* rank 0 sends each rank a status, then its part if the status is 1:
       a part it fails to cut stops the ranks still waiting, not hangs them */
    if (rank == 0) {
        int ok = 1;
        for (int r = P - 1; r >= 0; r--) {
            void *part = NULL;
            lci_dp_window wr;
            memset(&wr, 0, sizeof wr);
            if (ok) s = lci_dp_grid_plan(dev, shape, P, r, dt, &wr);
            if (ok && s == LC_OK && (!(part = lci_dp_grid_cut(whole.desc, wr.start, wr.count)) ||
                                     (r > 0 && lci_test_fault("scatter"))))
                s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for the part of rank %d", path, r);
            ok = ok && s == LC_OK;
            if (r == 0) {
                if (ok) *data = part;
                else free(part);
                break;
            }
            MPI_Send(&ok, 1, MPI_INT, r, 6, comm);
            size_t nb = ok ? (size_t)wr.count[0] * (size_t)wr.count[1] * (size_t)wr.count[2] * (size_t)es : 0;
            for (size_t o = 0; o < nb; o += (size_t)1 << 30) {
                size_t n = nb - o < ((size_t)1 << 30) ? nb - o : ((size_t)1 << 30);
                MPI_Send((char *)part + o, (int)n, MPI_BYTE, r, 7, comm);
            }
            free(part);
        }
        lci_loaded_free(&whole);
        return lc_mpi_agree(dev, comm, s);
    }
    int ok = 0;
    MPI_Recv(&ok, 1, MPI_INT, 0, 6, comm, MPI_STATUS_IGNORE);
    for (size_t o = 0; ok && o < bytes; o += (size_t)1 << 30) {
        size_t n = bytes - o < ((size_t)1 << 30) ? bytes - o : ((size_t)1 << 30);
        MPI_Recv((char *)*data + o, (int)n, MPI_BYTE, 0, 7, comm, MPI_STATUS_IGNORE);
    }
    if (!ok) s = lci_error(dev, LC_ERROR_INTERNAL, "%s: rank 0 sent no part", path);
    s = lc_mpi_agree(dev, comm, s);
    if (s != LC_OK) free(*data), *data = NULL;
    return s;
}

static lc_status load_grid(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld, const char *format,
                           float dt, lc_volume **out)
{
    int rank, P;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &P);
    lci_vol_layout *lay = calloc(1, sizeof *lay);
    lc_grid_desc shape;
    memset(&shape, 0, sizeof shape);
    lc_status s = lay ? kind_options(dev, path, ld, format, &shape) : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "out of memory");
    int whole = 0;
    char why[96] = "";
    if (s == LC_OK) {
        int brick = shape.brick;
        lc_grid_layout layout = shape.layout;
        s = ld->frame == 0 || !strcmp(format, "nifti") ? lci_dp_grid_layout(dev, path, ld, format, lay)
                                                      : LC_ERROR_UNSUPPORTED;
        if (s == LC_ERROR_UNSUPPORTED) {
            const char *e = lc_device_last_error(dev);
            size_t np = strlen(path); /* the message names the file: the note need not */
            snprintf(why, sizeof why, "%s", !strncmp(e, path, np) && !strncmp(e + np, ": ", 2) ? e + np + 2 : e);
            whole = 1, s = LC_OK;
        }
        if (s == LC_OK && !whole) shape = lay->grid, shape.brick = brick, shape.layout = layout;
    }
    /* every rank takes the same way (a file read whole on one rank is read whole by all) */
    int any = whole;
    MPI_Allreduce(&whole, &any, 1, MPI_INT, MPI_MAX, comm);
    s = lc_mpi_agree(dev, comm, s);
    lci_dp_window w;
    void *data = NULL;
    if (s == LC_OK && any) {
        free(lay);
        /* lci_read_grid reads first frames of grid formats: other frames and
           containers of several kinds (HDF5) are read whole by every rank */
        if (ld->frame != 0 || format_kind(format) != LC_KIND_GRID) {
            s = lc_volume_load(dev, path, ld, out);
            if (s == LC_OK)
                snprintf((*out)->read_note, sizeof (*out)->read_note, "the whole file (%s): every rank",
                         ld->frame != 0 ? "a frame past the first" : "a container of several kinds");
            return lc_mpi_agree(dev, comm, s);
        }
        s = scatter_grid(dev, comm, rank, P, path, ld, dt, &shape, &w, &data);
        lay = NULL;
    } else if (s == LC_OK) {
        s = lci_dp_grid_plan(dev, &shape, P, rank, dt, &w);
        if (s == LC_OK) s = lci_dp_grid_read(dev, path, lay, w.start, w.count, &data);
    }
    free(lay);
    float *bmin = NULL, *bmax = NULL;
    size_t nb = 0;
    if (s == LC_OK) s = lci_dp_grid_ranges(dev, &shape, &w, data, &bmin, &bmax, &nb);
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK) { /* the whole grid's leaf ranges on every rank */
        for (size_t o = 0; o < nb; o += (size_t)1 << 28) {
            int n = (int)(nb - o < ((size_t)1 << 28) ? nb - o : ((size_t)1 << 28));
            MPI_Allreduce(MPI_IN_PLACE, bmin + o, n, MPI_FLOAT, MPI_MIN, comm);
            MPI_Allreduce(MPI_IN_PLACE, bmax + o, n, MPI_FLOAT, MPI_MAX, comm);
        }
        MPI_Comm *c = malloc(sizeof *c);
        if (!c || MPI_Comm_dup(comm, c) != MPI_SUCCESS) {
            free(c);
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        } else {
            s = lci_dp_grid_create(dev, &shape, &w, data, bmin, bmax, P, rank, sum_counts, c, free_comm, out);
            if (s != LC_OK) free_comm(c);
            else if (any) /* why: rank 0's reason; a rank that had one reads its own */
                snprintf((*out)->read_note, sizeof (*out)->read_note, "its part of rank 0's whole read (%s)",
                         why[0] ? why : "another rank's file is read whole");
            else
                snprintf((*out)->read_note, sizeof (*out)->read_note, "nodes %d..%d x %d..%d x %d..%d of the file",
                         w.start[0], w.start[0] + w.count[0] - 1, w.start[1], w.start[1] + w.count[1] - 1,
                         w.start[2], w.start[2] + w.count[2] - 1);
        }
    }
    free(bmin), free(bmax), free(data);
    return lc_mpi_agree(dev, comm, s);
}

lc_status lc_mpi_volume_load(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *desc, float dt,
                             lc_volume **out)
{
    if (out) *out = NULL;
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_volume_load: device is NULL");
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_volume_load: MPI is not initialised (MPI_Init)");
    lc_status s = LC_OK;
    if (!path || !out) s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_volume_load: path and out must not be NULL");
    static const lc_load_desc none = {0};
    const lc_load_desc *ld = desc ? desc : &none;
    lc_file_info fi;
    if (s == LC_OK) s = lc_file_probe(dev, path, ld, &fi);
    s = lc_mpi_agree(dev, comm, s);
    if (s != LC_OK) return s;
    if (fi.kind == LC_KIND_GRID) {
        s = load_grid(dev, comm, path, ld, fi.format, dt, out);
        if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
        return s;
    }
    if (fi.kind == LC_KIND_PARTICLES) {
        s = lci_mpi_load_particles(dev, comm, path, ld, fi.format, dt, out);
        if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
        return s;
    }
    s = lci_mpi_load_rbf(dev, comm, path, ld, dt, out);
    if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
    return s;
}
