/* lanecast render under mpirun (cli_mpi.h). */
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include "cli_mpi.h"
#include "cli.h"
#include "lc_config.h"
#if LC_HAVE_MPI
#include "lanecast/lanecast_mpi.h"
#endif

static int started, nranks = 1, myrank = 0;
#if LC_HAVE_MPI
static int agreed_failure; /* every rank knows of a failure: they finish MPI normally */
#endif

/* The rank count the launcher (OpenMPI, MPICH/Hydra, PMIx) put in the environment; 1 when none. */
static int launched_ranks(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"};
    for (int i = 0; i < 3; i++) {
        const char *v = getenv(vars[i]);
        if (v && atoi(v) > 0) return atoi(v);
    }
    return 1;
}

int cli_mpi_begin(const char *cmd)
{
    int n = launched_ranks();
    if (n <= 1) return 0;
#if LC_HAVE_MPI
    int provided = 0;
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "%s: MPI_Init_thread failed\n", cmd);
        return CLI_EXIT_FAIL;
    }
    started = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &nranks);
    MPI_Comm_rank(MPI_COMM_WORLD, &myrank);
    return 0;
#else
    fprintf(stderr,
            "%s: started as one of %d MPI ranks, but this build of lanecast has no MPI (install libopenmpi-dev and rebuild)\n",
            cmd, n);
    return CLI_EXIT_FAIL;
#endif
}

int cli_mpi_end(int rc)
{
#if LC_HAVE_MPI
    /* A rank that fails outside a collective (a file it cannot open, before
       the ranks agree) would leave the others waiting in one: a failure
       aborts the whole job instead, after the rank printed its message. */
    fflush(stdout);
    fflush(stderr);
    if (started && rc != 0 && !agreed_failure) MPI_Abort(MPI_COMM_WORLD, rc);
    if (started) MPI_Finalize();
#endif
    started = 0;
    return rc;
}

int cli_mpi_launched(void) { return launched_ranks() > 1; }
int cli_mpi_ranks(void) { return nranks; }
int cli_mpi_rank(void) { return myrank; }

lc_status cli_mpi_agree(lc_device *dev, lc_status s)
{
#if LC_HAVE_MPI
    if (started) {
        s = lc_mpi_agree(dev, MPI_COMM_WORLD, s);
        agreed_failure |= s != LC_OK;
    }
#else
    (void)dev;
#endif
    return s;
}

lc_status cli_mpi_load(lc_device *dev, const char *path, const lc_load_desc *ld, float dt, lc_volume **out)
{
#if LC_HAVE_MPI
    if (started) {
        lc_status s = lc_mpi_volume_load(dev, MPI_COMM_WORLD, path, ld, dt, out);
        agreed_failure |= s != LC_OK;
        return s;
    }
#endif
    (void)dt;
    return lc_volume_load(dev, path, ld, out);
}

#if LC_HAVE_MPI
enum { NSTAT = 9 };

/* This process's peak resident memory in MB (getrusage: kilobytes on Linux). */
static double peak_mb(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? (double)ru.ru_maxrss / 1024.0 : 0.0;
}

static void print_ranks(const lc_mpi_stats *m)
{
    double mine[NSTAT] = {(double)m->region, (double)m->region_weight, m->render_seconds, m->composite_seconds,
                          (double)m->bytes_sent, (double)m->messages_sent, (double)m->rounds, (double)m->render.samples, peak_mb()};
    enum { NREAD = (int)sizeof m->read };
    double *all = myrank == 0 ? malloc(sizeof(double) * NSTAT * (size_t)nranks) : NULL;
    char *reads = myrank == 0 ? calloc((size_t)nranks, NREAD) : NULL;
    MPI_Gather(mine, NSTAT, MPI_DOUBLE, all, NSTAT, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    MPI_Gather(m->read, NREAD, MPI_CHAR, reads, NREAD, MPI_CHAR, 0, MPI_COMM_WORLD);
    if (myrank != 0) return;
    if (!all || !reads) {
        free(all), free(reads);
        return;
    }
    printf("mpi           %d ranks, %s, render imbalance %.3f (max / mean render time %.4f / %.4f s)\n", nranks,
           m->chain ? "the chain (dvr to the bit; rounds = bands)" : "binary swap",
           m->render_mean > 0.0 ? m->render_max / m->render_mean : 1.0, m->render_max, m->render_mean);
    printf("rank region     weight   render_s  composite_s      bytes  messages  rounds    samples  peak_MB  read\n");
    for (int r = 0; r < nranks; r++) {
        const double *v = all + (size_t)r * NSTAT;
        const char *rd = reads + (size_t)r * NREAD;
        printf("%4d %6.0f %10.0f %10.4f %12.4f %10.0f %9.0f %7.0f %10.0f %8.1f  %.*s\n", r, v[0], v[1], v[2], v[3],
               v[4], v[5], v[6], v[7], v[8], NREAD, rd[0] ? rd : "-");
    }
    free(all), free(reads);
}
#endif

lc_status cli_mpi_render(lc_device *dev, const lc_render_desc *d, int composite, int bands, float *rgba, int stats,
                         lc_render_stats *st)
{
#if LC_HAVE_MPI
    lc_mpi_stats m;
    lc_mpi_options o = {(lc_mpi_compositing)composite, bands};
    lc_status s = lc_mpi_render_with(dev, MPI_COMM_WORLD, 0, d, &o, rgba, &m);
    agreed_failure |= s != LC_OK;
    *st = m.render;
    st->seconds = m.render_seconds + m.composite_seconds;
    if (s == LC_OK && stats) print_ranks(&m);
    return s;
#else
    (void)stats, (void)composite, (void)bands;
    return lc_render(dev, d, rgba, st);
#endif
}
