/* lanecast info FILE: what lanecast makes of a file, through the public
 * calls only: lc_file_probe (format, kind, frames), lc_volume_load and
 * lc_volume_get_info (bounds, fields, value range), then the kind's own
 * lines (counts, radii or sizes and spacing) from its cli_kind row. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cli.h"
#include "render_opts.h"

static const char info_help[] =
    "usage: lanecast info FILE... [--frame N] [--topology FILE] [--series N|UID] [--format NAME]\n"
    "                     [--option KEY=VALUE ...]\n"
    "\n"
    "Prints what lanecast reads from FILE: its format and kind, the number of frames (trajectories),\n"
    "then, after loading the frame asked for (default 0): the particle or voxel count, the bounds,\n"
    "the fields, the default value range, radii or voxel spacing. FILE may be a folder or several\n"
    "files of a DICOM series; every series of the input is listed first (size, spacing, modality,\n"
    "rescale, transfer syntax); with several series and no --series, the listing ends with the\n"
    "error that asks for one (exit status 1).\n"
    "\n"
    "  --frame N             the frame to load (default 0)\n"
    "  --topology FILE       a companion file (a DCD's PSF, an XTC/TRR's .gro/.pdb/.psf topology)\n"
    "  --series N|UID        DICOM: the series to load, when the input holds several\n"
    "  --format NAME         the format, when it cannot be detected (see lanecast formats)\n"
    "  --option KEY=VALUE    a load option of the format or kind (lanecast formats lists them),\n"
    "                        e.g. --option fields=element; may be repeated\n"
    "  and every input flag of lanecast render, as render takes it: raw volumes (--dims, --type,\n"
    "  --spacing, --big-endian), particles (--raw-particles, --radius, --select, --value, --fields, ...)\n"
    "  and RBF sets (see lanecast render --help)\n"
    "\n"
    "example: lanecast info adk.dcd --topology adk.psf --frame 50\n"
    "         lanecast info ct.raw --dims 512,512,300 --type uint16 --spacing 0.5,0.5,1\n"
    "         lanecast info ct_folder/ --series 2\n"
    "\n"
    "exit status: 0 ok, 1 the file cannot be read (one message on stderr), 2 bad usage\n";

static void log_warning(void *user, lc_log_level level, const char *msg)
{
    (void)user;
    if (level == LC_LOG_WARNING) fprintf(stderr, "lanecast info: warning: %s\n", msg);
}

int cli_info(int argc, char **argv)
{
    const char *cmd = "lanecast info", *path = NULL;
    lc_load_desc ld = {0};
    lc_option opts[CLI_MAX_OPTIONS];
    char keys[CLI_MAX_OPTIONS][96];
    static cli_load load; /* the input flags (cli_input_flag); static: the values outlive the loop */
    const char *first[NKINDS] = {0};
    int nopt = 0, files_at = -1;
    char *files = NULL; /* several inputs: one per line */
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int r = cli_input_flag(cmd, argc, argv, &i, &load, first);
        if (r < 0) return CLI_EXIT_USAGE;
        if (r) continue;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) return fputs(info_help, stdout), 0;
        int takes = !strcmp(a, "--frame") || !strcmp(a, "--topology") || !strcmp(a, "--format") ||
                    !strcmp(a, "--option") || !strcmp(a, "--series");
        if (takes && i + 1 >= argc) {
            fprintf(stderr, "%s: %s needs a value\n", cmd, a);
            return free(files), CLI_EXIT_USAGE;
        }
        if (!strcmp(a, "--frame")) {
            char *end;
            long long f = strtoll(argv[++i], &end, 10);
            if (end == argv[i] || *end || f < 0) {
                fprintf(stderr, "%s: --frame: '%s' is not a frame number (0, 1, ...)\n", cmd, argv[i]);
                return free(files), CLI_EXIT_USAGE;
            }
            ld.frame = f;
        } else if (!strcmp(a, "--topology")) {
            ld.companion = argv[++i];
        } else if (!strcmp(a, "--format")) {
            ld.format = argv[++i];
        } else if (!strcmp(a, "--series")) {
            if (nopt == CLI_MAX_OPTIONS) {
                fprintf(stderr, "%s: too many options\n", cmd);
                return free(files), CLI_EXIT_USAGE;
            }
            opts[nopt].key = "series";
            opts[nopt++].value = argv[++i];
        } else if (!strcmp(a, "--option")) {
            const char *kv = argv[++i], *eq = strchr(kv, '=');
            if (!eq || eq == kv || nopt == CLI_MAX_OPTIONS || (size_t)(eq - kv) >= sizeof keys[0]) {
                fprintf(stderr, "%s: --option: expected KEY=VALUE, got '%s'\n", cmd, kv);
                return free(files), CLI_EXIT_USAGE;
            }
            snprintf(keys[nopt], sizeof keys[0], "%.*s", (int)(eq - kv), kv);
            opts[nopt].key = keys[nopt];
            opts[nopt].value = eq + 1;
            nopt++;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", cmd, a, cmd);
            return free(files), CLI_EXIT_USAGE;
        } else if (!path) {
            path = a;
        } else { /* the files of a DICOM series */
            if (cli_files_append(&files, path, a) || (files_at < 0 && nopt == CLI_MAX_OPTIONS)) {
                fprintf(stderr, "%s: out of room for the list of inputs\n", cmd);
                return free(files), CLI_EXIT_USAGE;
            }
            if (files_at < 0) files_at = nopt++;
            opts[files_at].key = "files";
            opts[files_at].value = files;
        }
    }
    if (!path) {
        fprintf(stderr, "%s: no input file (see %s --help)\n", cmd, cmd);
        return CLI_EXIT_USAGE;
    }
    lc_option all[2 * CLI_MAX_OPTIONS];
    int nall = cli_input_merge(cmd, &load, opts, nopt, all, 2 * CLI_MAX_OPTIONS);
    if (nall < 0) return CLI_EXIT_USAGE;
    if (!ld.format) ld.format = load.format;
    ld.options = all;
    ld.noptions = nall;
    lc_device *dev = NULL;
    lc_device_desc dd = {.threads = 1, .log = log_warning};
    if (lc_device_create(&dd, &dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
        return free(files), CLI_EXIT_FAIL;
    }
    int rc = CLI_EXIT_FAIL;
    lc_volume *v = NULL;
    lc_file_info fi;
    lc_volume_info vi;
    if (lc_file_probe(dev, path, &ld, &fi) != LC_OK) goto fail;
    printf("file          %s\n", path);
    printf("format        %s%s\n", fi.format, fi.gzip ? " (gzip)" : "");
    printf("kind          %s\n", lc_kind_name(fi.kind));
    if (fi.frames > 0) printf("frames        %lld\n", (long long)fi.frames);
    else printf("frames        unknown (the file could not be counted; loading says why)\n");
    static char about[1 << 16];
    if (lc_file_describe(dev, path, &ld, about, sizeof about) != LC_OK) goto fail;
    fputs(about, stdout);
    fflush(stdout);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (lc_volume_load(dev, path, &ld, &v) != LC_OK || lc_volume_get_info(v, &vi) != LC_OK) goto fail;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("frame         %lld (the one loaded)\n", (long long)ld.frame);
    printf("bounds        %g %g %g .. %g %g %g\n", (double)vi.bounds.lo.x, (double)vi.bounds.lo.y,
           (double)vi.bounds.lo.z, (double)vi.bounds.hi.x, (double)vi.bounds.hi.y, (double)vi.bounds.hi.z);
    printf("fields        %d\n", vi.nfields);
    printf("range         %g .. %g (the default value range a transfer function maps)\n", (double)vi.range[0],
           (double)vi.range[1]);
    const cli_kind *row = cli_kind_of(fi.kind);
    if (row) row->print_stats(v, (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec), stdout);
    rc = 0;
    goto out;
fail:
    fflush(stdout);
    fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
out:
    lc_volume_destroy(v);
    lc_device_destroy(dev);
    free(files);
    return rc;
}
