/* The command line under mpirun (tools/cli_mpi.c): lanecast render notices
 * it was started as one of several MPI ranks, initialises MPI and renders
 * data-parallel (lc_mpi_render); one rank, or no mpirun, renders as
 * always, without touching MPI. */
#ifndef LC_CLI_MPI_H
#define LC_CLI_MPI_H

#include "lanecast/lanecast.h"

/* Initialises MPI when the environment says this process is one of more
 * than one ranks. 0 on success (also without MPI), else an exit status
 * (after printing one line: a build without MPI). */
int cli_mpi_begin(const char *cmd);
/* Finalises MPI if cli_mpi_begin initialised it (rc != 0: aborts every
 * rank, so none waits for this one); returns rc. */
int cli_mpi_end(int rc);
/* 1 when the environment says this process is one of several MPI ranks
 * (before cli_mpi_begin too). */
int cli_mpi_launched(void);
/* Ranks (1 without MPI) and this process's rank (0 without MPI). */
int cli_mpi_ranks(void);
int cli_mpi_rank(void);
/* The status every rank agrees on (lc_mpi_agree); s itself with one rank. */
lc_status cli_mpi_agree(lc_device *dev, lc_status s);
/* Under MPI lc_mpi_volume_load on all ranks (each reads its region's part
 * where the format allows; dt: the render's step); else lc_volume_load. */
lc_status cli_mpi_load(lc_device *dev, const char *path, const lc_load_desc *ld, float dt, lc_volume **out);
/* lc_mpi_render over all ranks, root 0; st gets this rank's region render
 * counters (seconds: render and composite). With stats, rank 0 prints a
 * line per rank: its region, weight, render and composite seconds, bytes
 * and messages sent, compositing steps, samples, its peak resident memory
 * (getrusage ru_maxrss, MB) and the imbalance. */
lc_status cli_mpi_render(lc_device *dev, const lc_render_desc *d, int composite, int bands, float *rgba, int stats,
                         lc_render_stats *st);

#endif
