/* The chain (lc_mpi_options LC_MPI_CHAIN): dvr to the bit. The image goes
 * from rank to rank in the kd-tree's visibility order, a band of rows at a
 * time; each rank's rays go on from the (C, A) the regions in front of it
 * left (lci_dp_chain, lc_ktile carry), so every pixel gets one process's
 * blending operations in one process's order, and the last rank sends the
 * finished bands to root. Band b of rank p overlaps band b + 1 of rank
 * p - 1: the chain fills in P - 1 band times, then runs like the ranks'
 * slowest. Every rank sends every band: a flag first, then the rows unless
 * the flag says that this rank or one before it failed; a failure thus runs
 * down the chain instead of leaving a rank waiting, and the agreement at
 * the end gives every rank the failing rank's message. */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>
#include "host/mpi/mpi_internal.h"

enum { TAG_FLAG = 200, TAG_ROWS = 201, TAG_ROOT_FLAG = 202, TAG_ROOT_ROWS = 203, TAGS = 4 };

typedef struct chain_run {
    MPI_Comm comm;
    int rank, root, bands;
    lci_cimage view; /* the rank's image, for packing a band's non-empty rect */
    float *pack;     /* the bands as sent: each at band b's first row's offset + 4 b floats */
    float *in;       /* a band received, packed */
    MPI_Request *req;
    int *flags;
    int nreq;
    uint64_t bytes, msgs;
} chain_run;

static int tag(int b, int kind) { return TAGS * b + kind; }

/* Band b (rows [y0, y1)) to dest without waiting: its flag (0: rows follow)
 * and, when ok, the bounding rectangle of its non-empty pixels (lci_cpack):
 * outside it the band is transparent, as a receiver's image is before. */
static int post(chain_run *c, int dest, int b, int kind, int ok, int y0, int y1)
{
    c->flags[b] = ok ? 0 : 1;
    int rc = MPI_Isend(&c->flags[b], 1, MPI_INT, dest, tag(b, kind), c->comm, &c->req[c->nreq++]);
    c->msgs++;
    if (rc == MPI_SUCCESS && ok) {
        float *buf = c->pack + 4 * (size_t)c->view.w * (size_t)y0 + 4 * (size_t)b;
        lci_cimage_rect_rows(&c->view, LCI_COMP_OVER, y0, y1);
        size_t n = lci_cpack(&c->view, LCI_COMP_OVER, y0, y1, buf);
        rc = MPI_Isend(buf, (int)n, MPI_FLOAT, dest, tag(b, kind + 1), c->comm, &c->req[c->nreq++]);
        c->bytes += n * sizeof(float), c->msgs++;
    }
    return rc;
}

/* Band b's flag and, when it says so, its rows [y0, y1) from src into out
 * (w wide): 1 when they came. */
static int take(chain_run *c, int src, int b, int kind, int y0, int y1, float *out, int *rc)
{
    int flag = 1;
    *rc = MPI_Recv(&flag, 1, MPI_INT, src, tag(b, kind), c->comm, MPI_STATUS_IGNORE);
    if (*rc != MPI_SUCCESS || flag) return 0;
    size_t cap = lci_cpack_max(c->view.w, y1 - y0, LCI_COMP_OVER);
    *rc = MPI_Recv(c->in, (int)cap, MPI_FLOAT, src, tag(b, kind + 1), c->comm, MPI_STATUS_IGNORE);
    if (*rc != MPI_SUCCESS) return 0;
    lci_cunpack(c->in, c->view.w, y0, y1, out);
    return 1;
}

lc_status lci_mpi_chain(lc_device *dev, MPI_Comm comm, int root, const lc_render_desc *d, const lci_kdtree *t,
                        const int *order, const int *pos_of, int bands, float *rgba, lc_mpi_stats *st)
{
    chain_run c;
    memset(&c, 0, sizeof c);
    c.comm = comm, c.root = root, c.bands = bands;
    int P;
    MPI_Comm_rank(comm, &c.rank);
    MPI_Comm_size(comm, &P);
    const int pos = pos_of[c.rank], last = order[P - 1];
    const int prev = pos > 0 ? order[pos - 1] : -1, next = pos < P - 1 ? order[pos + 1] : -1;
    const size_t W = (size_t)d->width, H = (size_t)d->height;
    double t0 = MPI_Wtime(), render = 0.0;
    float *img = calloc(4 * W * H, sizeof(float));
    int most = 0; /* rows of the tallest band */
    for (int b = 0; b < bands; b++) {
        int n = lci_dp_band_row(d->height, bands, b + 1) - lci_dp_band_row(d->height, bands, b);
        most = n > most ? n : most;
    }
    c.view = (lci_cimage){d->width, d->height, img, NULL, {0, 0, 0, 0}};
    c.pack = malloc(sizeof(float) * (4 * W * H + 4 * (size_t)bands));
    c.in = malloc(sizeof(float) * lci_cpack_max(d->width, most, LCI_COMP_OVER));
    c.req = malloc(sizeof(MPI_Request) * 2 * (size_t)bands);
    c.flags = malloc(sizeof(int) * (size_t)bands);
    lci_dp_chain ch;
    memset(&ch, 0, sizeof ch);
    lc_status s = LC_OK;
    if (!img || !c.pack || !c.in || !c.req || !c.flags)
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_mpi_render: out of memory for a %dx%d chain image", d->width,
                      d->height);
    else
        s = lci_dp_chain_begin(dev, d, t, c.rank, &ch);
    /* what can fail before the first band, agreed on: then every rank has
       its image and buffers, and only a cancel can stop a band */
    s = lc_mpi_agree(dev, comm, s);
    const int started = s == LC_OK; /* the same on every rank */
    int up = 1, rc = MPI_SUCCESS;   /* up: every rank before this one rendered every band so far */
    for (int b = 0; b < bands && started; b++) {
        int y0 = lci_dp_band_row(d->height, bands, b), y1 = lci_dp_band_row(d->height, bands, b + 1);
        if (prev >= 0 && up) up = take(&c, prev, b, TAG_FLAG, y0, y1, img, &rc);
        else if (prev >= 0) take(&c, prev, b, TAG_FLAG, y0, y1, img, &rc); /* the flags still come */
        if (rc != MPI_SUCCESS) break;
        if (up && s == LC_OK) {
            double r0 = MPI_Wtime();
            s = lci_dp_chain_rows(dev, &ch, d, img, y0, y1);
            render += MPI_Wtime() - r0;
        }
        int ok = up && s == LC_OK;
        if (next >= 0) rc = post(&c, next, b, TAG_FLAG, ok, y0, y1);
        else if (c.rank != root) rc = post(&c, root, b, TAG_ROOT_FLAG, ok, y0, y1);
        else if (ok) memcpy(rgba + 4 * W * (size_t)y0, img + 4 * W * (size_t)y0, sizeof(float) * 4 * W * (size_t)(y1 - y0));
        if (rc != MPI_SUCCESS) break;
    }
    if (started && rc == MPI_SUCCESS && c.rank == root && last != root)
        for (int b = 0; b < bands; b++) { /* the finished bands from the last rank */
            int y0 = lci_dp_band_row(d->height, bands, b), y1 = lci_dp_band_row(d->height, bands, b + 1);
            take(&c, last, b, TAG_ROOT_FLAG, y0, y1, rgba, &rc);
            if (rc != MPI_SUCCESS) break;
        }
    if (c.nreq && MPI_Waitall(c.nreq, c.req, MPI_STATUSES_IGNORE) != MPI_SUCCESS && rc == MPI_SUCCESS) rc = MPI_ERR_OTHER;
    if (s == LC_OK && rc != MPI_SUCCESS)
        s = lci_error(dev, LC_ERROR_INTERNAL, "lc_mpi_render: a message of the chain failed (MPI error %d)", rc);
    st->render = ch.stats;
    st->render_seconds = render;
    st->composite_seconds = MPI_Wtime() - t0 - render;
    st->bytes_sent = c.bytes, st->messages_sent = c.msgs, st->rounds = bands;
    lci_dp_chain_end(&ch);
    free(img), free(c.pack), free(c.in), free(c.req), free(c.flags);
    return s;
}
