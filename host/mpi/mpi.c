/* lc_mpi_render (include/lanecast/lanecast_mpi.h): one kd-tree region per
 * rank, rendered on the global lattice (host/mpi/regions.c), composited by
 * the schedule of host/mpi/composite.c over MPI. After every collective
 * step the ranks agree on a status (an allreduce), so a rank that failed
 * makes every rank return its message instead of leaving a peer waiting. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/mpi/dp.h"
#include "host/mpi/mpi_internal.h"
#include "lanecast/lanecast_mpi.h"

lc_status lc_mpi_agree(lc_device *dev, MPI_Comm comm, lc_status s)
{
    int rank;
    MPI_Comm_rank(comm, &rank);
    /* (0 = failed, rank): MINLOC gives the lowest failing rank */
    int mine[2] = {s != LC_OK ? 0 : 1, rank}, worst[2];
    if (MPI_Allreduce(mine, worst, 1, MPI_2INT, MPI_MINLOC, comm) != MPI_SUCCESS)
        return lci_error(dev, LC_ERROR_INTERNAL, "lc_mpi_render: MPI_Allreduce of the status failed");
    if (worst[0]) return LC_OK;
    int who = worst[1];
    char msg[LCI_MSG_MAX];
    int code = (int)s;
    if (rank == who) snprintf(msg, sizeof msg, "%s", lc_device_last_error(dev));
    MPI_Bcast(&code, 1, MPI_INT, who, comm);
    MPI_Bcast(msg, (int)sizeof msg, MPI_CHAR, who, comm);
    msg[sizeof msg - 1] = 0;
    if (rank == who) return s; /* its own message stands */
    /* a failure agreed on before (steps that agree again on the way out):
       its message already names the rank it came from */
    int from = -1, at = 0;
    if (sscanf(msg, "rank %d: %n", &from, &at) == 1 && at > 0) return lci_error(dev, (lc_status)code, "%s", msg);
    return lci_error(dev, (lc_status)code, "rank %d: %s", who, msg);
}

typedef struct mpi_run {
    lc_device *dev;
    MPI_Comm comm;
    int rank, P, root;
    const lc_render_desc *d;
    lc_mpi_options opt;
    lci_kdtree tree;
    int *order, *pos_of; /* visibility position -> region (= rank) and back */
    lci_cimage img;
    float *buf[2];
    size_t cap;
    lc_mpi_stats st;
    lci_mpi_cstats *cs; /* per-step timings (lci_mpi_composite), or NULL */
} mpi_run;

static lc_status mpi_fail(mpi_run *r, int code, const char *what)
{
    char e[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(code, e, &len);
    return lci_error(r->dev, LC_ERROR_INTERNAL, "lc_mpi_render: %s failed: %s", what, e);
}

static void step_done(mpi_run *r, double t0, uint64_t bytes, uint64_t pixels)
{
    if (!r->cs || r->cs->nsteps >= LCI_CSTEPS_MAX + 1) return;
    int i = r->cs->nsteps++;
    r->cs->seconds[i] = MPI_Wtime() - t0;
    r->cs->bytes[i] = bytes;
    r->cs->pixels[i] = pixels;
}

/* The schedule's fold and swap steps of this rank. */
static lc_status swap_steps(mpi_run *r, int op, int *own0, int *own1)
{
    lci_cstep steps[LCI_CSTEPS_MAX];
    int pos = r->pos_of[r->rank];
    int ns = lci_cschedule(r->P, pos, r->img.h, steps, own0, own1);
    for (int i = 0; i < ns; i++) {
        const lci_cstep *s = &steps[i];
        int has_send = s->send_y1 > s->send_y0, has_recv = s->recv_y1 > s->recv_y0;
        if (!has_send && !has_recv) continue;
        double t0 = MPI_Wtime();
        int peer = r->order[s->partner], rc = MPI_SUCCESS;
        size_t n = has_send ? lci_cpack(&r->img, op, s->send_y0, s->send_y1, r->buf[0]) : 0;
        MPI_Status ms;
        if (has_send && has_recv)
            rc = MPI_Sendrecv(r->buf[0], (int)n, MPI_FLOAT, peer, 1 + i, r->buf[1], (int)r->cap, MPI_FLOAT, peer,
                              1 + i, r->comm, &ms);
        else if (has_send)
            rc = MPI_Send(r->buf[0], (int)n, MPI_FLOAT, peer, 1 + i, r->comm);
        else
            rc = MPI_Recv(r->buf[1], (int)r->cap, MPI_FLOAT, peer, 1 + i, r->comm, &ms);
        if (rc != MPI_SUCCESS) return mpi_fail(r, rc, "a compositing message");
        if (has_send) r->st.bytes_sent += n * sizeof(float), r->st.messages_sent++;
        uint64_t px = has_recv ? lci_cpacked_pixels(r->buf[1]) : 0;
        if (has_recv) lci_cblend(&r->img, op, r->buf[1], s->front);
        r->st.rounds++;
        step_done(r, t0, n * sizeof(float), px);
    }
    return LC_OK;
}

/* Every owner's composited rows to root. */
static lc_status gather(mpi_run *r, int op, int own0, int own1, float *rgba)
{
    const int tag = 100;
    double t0 = MPI_Wtime();
    if (r->rank != r->root) {
        if (own1 <= own0) return LC_OK;
        size_t n = lci_cpack(&r->img, op, own0, own1, r->buf[0]);
        int rc = MPI_Send(r->buf[0], (int)n, MPI_FLOAT, r->root, tag, r->comm);
        if (rc != MPI_SUCCESS) return mpi_fail(r, rc, "sending rows to root");
        r->st.bytes_sent += n * sizeof(float), r->st.messages_sent++, r->st.rounds++;
        step_done(r, t0, n * sizeof(float), 0);
        return LC_OK;
    }
    uint64_t px = 0;
    for (int p = 0; p < r->P; p++) {
        lci_cstep steps[LCI_CSTEPS_MAX];
        int y0, y1, src = r->order[p];
        lci_cschedule(r->P, p, r->img.h, steps, &y0, &y1);
        if (y1 <= y0) continue;
        if (src == r->rank) { /* its own rows straight from its image */
            lci_cunpack_own(&r->img, y0, y1, rgba);
            continue;
        }
        int rc = MPI_Recv(r->buf[1], (int)r->cap, MPI_FLOAT, src, tag, r->comm, MPI_STATUS_IGNORE);
        if (rc != MPI_SUCCESS) return mpi_fail(r, rc, "receiving rows at root");
        /* rows outside the sender's rect are transparent */
        lci_cunpack(r->buf[1], r->img.w, y0, y1, rgba);
        px += lci_cpacked_pixels(r->buf[1]);
    }
    step_done(r, t0, 0, px);
    return LC_OK;
}

/* The swap and the gather, each followed by an agreement. */
static lc_status composite(mpi_run *r, int op, float *rgba)
{
    int own0 = 0, own1 = 0;
    lc_status s = swap_steps(r, op, &own0, &own1);
    s = lc_mpi_agree(r->dev, r->comm, s);
    if (s != LC_OK) return s;
    s = gather(r, op, own0, own1, rgba);
    return lc_mpi_agree(r->dev, r->comm, s);
}

/* The two message buffers, kept from one composite to the next: fresh 16 MB
 * buffers (a 1024^2 image) were page-faulted and zeroed by the kernel on
 * every frame, a quarter of the composite time at P = 2 (perf:
 * clear_page_erms, exc_page_fault). Only the thread that talks MPI uses them
 * (MPI_THREAD_FUNNELED); freed at exit. */
static struct {
    float *p[2];
    size_t cap;
} scratch;

static void scratch_free(void)
{
    free(scratch.p[0]), free(scratch.p[1]);
    scratch.p[0] = scratch.p[1] = NULL, scratch.cap = 0;
}

static int scratch_get(size_t cap, float **buf)
{
    if (scratch.cap < cap) {
        static int registered;
        if (!registered) registered = atexit(scratch_free) == 0;
        scratch_free();
        scratch.p[0] = malloc(sizeof(float) * cap);
        scratch.p[1] = malloc(sizeof(float) * cap);
        if (!scratch.p[0] || !scratch.p[1]) {
            scratch_free();
            return -1;
        }
        scratch.cap = cap;
    }
    buf[0] = scratch.p[0], buf[1] = scratch.p[1];
    return 0;
}

lc_status lci_mpi_composite(lc_device *dev, MPI_Comm comm, int root, int op, lci_cimage *img, const int *order,
                            float *rgba, lci_mpi_cstats *cs)
{
    mpi_run r;
    memset(&r, 0, sizeof r);
    r.dev = dev, r.comm = comm, r.root = root, r.cs = cs;
    MPI_Comm_rank(comm, &r.rank);
    MPI_Comm_size(comm, &r.P);
    r.img = *img;
    r.order = (int *)order;
    r.pos_of = malloc(sizeof(int) * (size_t)r.P);
    r.cap = lci_cpack_max(img->w, img->h, op);
    lc_status s = LC_OK;
    if (!r.pos_of || scratch_get(r.cap, r.buf) != 0)
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "compositing: out of memory");
    for (int p = 0; s == LC_OK && p < r.P; p++) r.pos_of[order[p]] = p;
    if (cs) memset(cs, 0, sizeof *cs);
    s = lc_mpi_agree(dev, comm, s);
    double t0 = MPI_Wtime();
    if (s == LC_OK) s = composite(&r, op, rgba);
    if (cs) {
        cs->total_seconds = MPI_Wtime() - t0;
        cs->bytes_sent = r.st.bytes_sent, cs->messages_sent = r.st.messages_sent;
    }
    img->rect[0] = r.img.rect[0], img->rect[1] = r.img.rect[1], img->rect[2] = r.img.rect[2], img->rect[3] = r.img.rect[3];
    free(r.pos_of);
    return s;
}

/* The render times' mean and maximum over the ranks. */
static void render_spread(mpi_run *r)
{
    double sum = 0.0, mx = 0.0;
    MPI_Allreduce(&r->st.render_seconds, &sum, 1, MPI_DOUBLE, MPI_SUM, r->comm);
    MPI_Allreduce(&r->st.render_seconds, &mx, 1, MPI_DOUBLE, MPI_MAX, r->comm);
    r->st.render_mean = sum / r->P, r->st.render_max = mx;
}

static lc_status render_and_composite(mpi_run *r, float *rgba)
{
    lc_device *dev = r->dev;
    const lc_render_desc *d = r->d;
    lc_status s = lci_dp_partition(dev, d, r->P, &r->tree);
    lc_kcamera cam;
    if (s == LC_OK) s = lci_dp_camera(dev, d, &cam);
    if (s == LC_OK && r->rank == r->root && !rgba)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: rgba is NULL on the root rank");
    if (s == LC_OK) {
        r->order = malloc(sizeof(int) * (size_t)r->P);
        r->pos_of = malloc(sizeof(int) * (size_t)r->P);
        if (!r->order || !r->pos_of) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_mpi_render: out of memory");
    }
    double t0 = MPI_Wtime();
    if (s == LC_OK) {
        lci_kd_order(&r->tree, &cam, r->order);
        for (int p = 0; p < r->P; p++) r->pos_of[r->order[p]] = p;
        r->st.region = r->rank;
        r->st.region_weight = r->tree.weight[r->rank];
    }
    /* what the ranks chose alike (the same desc and options): no collective needed */
    if (d->mode == LC_MODE_DVR && r->opt.compositing != LC_MPI_SWAP) {
        s = lc_mpi_agree(dev, r->comm, s);
        if (s != LC_OK) return s;
        int bands = r->opt.bands > 0 ? r->opt.bands : r->P * 4 > 16 ? r->P * 4 : 16;
        bands = bands < d->height ? bands : d->height;
        bands = bands < 4096 ? bands : 4096; /* 4 tags a band stay below MPI's least MPI_TAG_UB, 32767 */
        r->st.chain = 1;
        s = lci_mpi_chain(dev, r->comm, r->root, d, &r->tree, r->order, r->pos_of, bands, rgba, &r->st);
        s = lc_mpi_agree(dev, r->comm, s);
        render_spread(r);
        return s;
    }
    if (s == LC_OK) s = lci_dp_render_region(dev, d, &r->tree, r->rank, &r->img, &r->st.render);
    int op = lci_dp_op(d);
    if (s == LC_OK) {
        r->cap = lci_cpack_max(r->img.w, r->img.h, op);
        if (scratch_get(r->cap, r->buf) != 0)
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_mpi_render: out of memory for compositing buffers");
    }
    r->st.render_seconds = MPI_Wtime() - t0;
    s = lc_mpi_agree(dev, r->comm, s);
    if (s != LC_OK) return s;
    double t1 = MPI_Wtime();
    s = composite(r, op, rgba);
    r->st.composite_seconds = MPI_Wtime() - t1;
    render_spread(r);
    return s;
}

lc_status lc_mpi_render(lc_device *dev, MPI_Comm comm, int root, const lc_render_desc *desc, float *rgba,
                        lc_mpi_stats *stats)
{
    return lc_mpi_render_with(dev, comm, root, desc, NULL, rgba, stats);
}

lc_status lc_mpi_render_with(lc_device *dev, MPI_Comm comm, int root, const lc_render_desc *desc,
                             const lc_mpi_options *opts, float *rgba, lc_mpi_stats *stats)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: device is NULL");
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: MPI is not initialised (MPI_Init)");
    mpi_run r;
    memset(&r, 0, sizeof r);
    r.dev = dev, r.d = desc, r.root = root;
    if (opts) r.opt = *opts;
    if (MPI_Comm_dup(comm, &r.comm) != MPI_SUCCESS)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: MPI_Comm_dup of the communicator failed");
    MPI_Comm_set_errhandler(r.comm, MPI_ERRORS_RETURN);
    MPI_Comm_rank(r.comm, &r.rank);
    MPI_Comm_size(r.comm, &r.P);
    r.st.rank = r.rank, r.st.ranks = r.P;
    if (desc && desc->volume) snprintf(r.st.read, sizeof r.st.read, "%s", desc->volume->read_note);
    lc_status s = LC_OK;
    if (root < 0 || root >= r.P)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: root %d, the communicator has ranks 0 .. %d",
                      root, r.P - 1);
    else if (!desc)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: desc is NULL");
    else if (r.opt.compositing < LC_MPI_AUTO || r.opt.compositing > LC_MPI_SWAP || r.opt.bands < 0)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_mpi_render: options compositing %d, bands %d (expected 0 .. 2, >= 0)",
                      (int)r.opt.compositing, r.opt.bands);
    /* a bad root is every rank's error alike: no collective needs it */
    if (s == LC_OK) s = render_and_composite(&r, rgba);
    if (stats) *stats = r.st;
    lci_cimage_free(&r.img);
    free(r.order);
    free(r.pos_of);
    lci_kd_release(&r.tree);
    MPI_Comm_free(&r.comm);
    return s;
}
