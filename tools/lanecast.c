/* lanecast: the command-line tool. Subcommands live in cmd_*.c. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

static const char usage[] =
    "lanecast " LC_VERSION_STRING " - CPU volume ray casting of particles and volumes\n"
    "\n"
    "usage: lanecast COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  render INPUT -o OUT   render particle data or a volume to an image\n"
    "                        (lanecast render --help for every option)\n"
    "  demo -o OUT           render the built-in demo scene (procedural, two fields)\n"
    "  encode INPUT -o OUT.rbf   fit an RBF set to a volume or scattered samples (CSV, VTK)\n"
    "                        (lanecast encode --help)\n"
    "  view INPUT            explore data in a window: progressive rendering, orbit, TF editor\n"
    "                        (lanecast view --help; needs the viewer feature and a display)\n"
    "  targets               list SIMD targets: compiled, supported by this CPU, active\n"
    "  formats               list the file formats (kind, extensions, options) and the\n"
    "                        optional features of this build (gzip input, JSON TFs)\n"
    "  bench                 check every SIMD target against scalar and time it over a case\n"
    "                        matrix, one JSON line per case (lanecast bench --help)\n"
    "  info FILE             what lanecast reads from FILE: format, kind, frames, count,\n"
    "                        bounds, fields, value range, spacing (lanecast info --help)\n"
    "  resample INPUT -o GRID.nrrd --dims N   deposit particles' field at grid nodes\n"
    "                        (lanecast resample --help)\n"
    "\n"
    "options:\n"
    "  --help, -h            this text\n"
    "  --version             print the version\n"
    "\n"
    "environment:\n"
    "  LANECAST_TARGET       force a target: scalar, sse4, avx2, avx512, avx512_8 or auto\n"
    "  LANECAST_THREADS      worker threads (default: all online CPUs)\n"
    "\n"
    "example: lanecast render 1tii.pdb -o 1tii.png   (every command's --help has more)\n"
    "\n"
    "exit status: 0 ok, 1 bad input or failed work, 2 bad usage\n";

/* host/api/image.c: unlinks the temporary images being written
 * (async-signal-safe). */
void lci_image_remove_temps(void);

/* Crash safety: an interrupted or terminated run leaves no temporary image
 * (outputs appear only by rename, so none is ever partial); the signal is
 * then delivered again with its default action, so the exit status still
 * says which one (130 for SIGINT, 143 for SIGTERM in a shell). */
static void on_signal(int sig)
{
    lci_image_remove_temps();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* Signals that were ignored when we started (nohup, background jobs of a
 * non-interactive shell) stay ignored. */
static void install_signal_handlers(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction old;
        if (sigaction(sigs[i], NULL, &old) != 0 || old.sa_handler == SIG_IGN) continue;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(sigs[i], &sa, NULL);
    }
}

int main(int argc, char **argv)
{
    install_signal_handlers();
    if (argc < 2) {
        fputs(usage, stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        fputs(usage, stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("lanecast %s\n", lc_version_string());
        return 0;
    }
    if (!strcmp(cmd, "targets")) return cli_targets(argc - 1, argv + 1);
    if (!strcmp(cmd, "formats")) return cli_formats(argc - 1, argv + 1);
    if (!strcmp(cmd, "render")) return cli_render(argc - 1, argv + 1);
    if (!strcmp(cmd, "demo")) return cli_demo(argc - 1, argv + 1);
    if (!strcmp(cmd, "info")) return cli_info(argc - 1, argv + 1);
    if (!strcmp(cmd, "encode")) return cli_encode(argc - 1, argv + 1);
    if (!strcmp(cmd, "bench")) return cli_bench(argc - 1, argv + 1);
    if (!strcmp(cmd, "resample")) return cli_resample(argc - 1, argv + 1);
    if (!strcmp(cmd, "view")) return cli_view(argc - 1, argv + 1);
    fprintf(stderr, "lanecast: unknown command '%s' (try lanecast --help)\n", cmd);
    return 2;
}
