/* lanecast encode: fits an RBF set to a volume or to scattered samples
 * (lc_samples_load, lc_rbf_encode) and writes it as a .rbf file
 * (lc_rbf_write). */
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "render_opts.h"

static const char encode_help[] =
    "usage: lanecast encode INPUT -o OUT.rbf [options]\n"
    "\n"
    "Encodes a scalar field as an RBF set (a bias plus truncated Gaussians, Jang et al. 2004 sec. 4)\n"
    "that `lanecast render OUT.rbf` draws. Clusters of the samples are split by PCA along the\n"
    "principal axis of the cluster with the largest error; each new RBF is centred in it, its\n"
    "width fitted by Levenberg-Marquardt and the weights and bias by linear least squares\n"
    "(LAPACKE), until the RMS error is at most --max-error of the value range or there are\n"
    "--max-rbfs RBFs. Each time the count has grown by a quarter, a polish sweep refits every\n"
    "RBF's weight, width and centre in turn against the residual (and up to 8 sweeps more when\n"
    "--max-rbfs is reached short of --max-error). The file is written under a temporary name and\n"
    "renamed when complete.\n"
    "\n"
    "input:\n"
    "  a structured volume    any volume format lanecast reads (lanecast formats: .nrrd/.nhdr,\n"
    "                         .mhd, raw with --format raw-volume --opt size=...); node positions\n"
    "                         follow its spacing and origin\n"
    "  .csv                   scattered samples: a header naming the columns x,y,z,value (any\n"
    "                         order, other columns ignored), one sample per line; '#' comments\n"
    "  .vtk                   VTK legacy POLYDATA or UNSTRUCTURED_GRID, ASCII or BINARY: its points\n"
    "                         and its first one-component point data array\n"
    "  --format NAME          read INPUT as this format (csv, vtk or a volume format)\n"
    "  --opt KEY=VALUE        a load option of the volume format (repeatable; e.g. size=64,64,64)\n"
    "  every input flag of lanecast render, as render takes it: raw volumes (--dims X,Y,Z, --type,\n"
    "                         --spacing, --big-endian) and the particle and RBF set flags\n"
    "                         (see lanecast render --help)\n"
    "\n"
    "fitting:\n"
    "  --max-error E          target RMS error relative to the value range, in (0, 1) (default 0.02)\n"
    "  --max-rbfs N           at most N RBFs (default 4096, at most the samples to fit - 1)\n"
    "  --centre mean|maxerr   new RBFs at the cluster's mean weighted by the value still to fit\n"
    "                         (default) or at its point of largest error\n"
    "  --fit-range LO,HI      fit only samples with values in [LO, HI] (the values of interest;\n"
    "                         the field elsewhere is unconstrained)\n"
    "  --fit-samples N        fit on a fixed-seed subsample of at most N samples (default 2097152;\n"
    "                         the report is over all of them)\n"
    "  --lm-samples N         samples Levenberg-Marquardt sees per step and per RBF in a polish\n"
    "                         sweep (default 2048)\n"
    "  --local-rbfs N         RBFs refitted per step: the new one and its nearest neighbours (default 4)\n"
    "  --seed N               subsampling seed (default 1)\n"
    "\n"
    "output:\n"
    "  -o OUT.rbf             binary .rbf (docs/FORMATS-rbf.md)\n"
    "  --text                 the text variant instead\n"
    "  --threads N            worker threads (default: all CPUs)\n"
    "  --progress             a progress line per step on stderr (default when stderr is a terminal;\n"
    "                         otherwise a line each time the RBF count doubles)\n"
    "  --quiet                print nothing but errors\n"
    "\n"
    "examples:\n"
    "  lanecast encode neghip.nhdr -o neghip.rbf\n"
    "  lanecast encode hydrogen.nhdr -o h.rbf --max-error 0.01 --centre maxerr\n"
    "  lanecast encode neghip.nhdr -o n.rbf --centre maxerr --max-rbfs 1024 --progress\n"
    "  lanecast encode shock.vtk -o shock.rbf --fit-range 0.6,1.7 --max-rbfs 3000\n"
    "  lanecast encode samples.csv -o s.rbf --text && lanecast render s.rbf -o s.png\n"
    "\n"
    "The final report gives the RBF count, the RMS and max error relative to the value range\n"
    "(with the truncation a loaded set uses), the compression ratio and the time.\n"
    "\n"
    "exit status: 0 ok (also when --max-rbfs stopped before --max-error; the report says so),\n"
    "1 bad input or failed work (one message on stderr, nothing written), 2 bad usage\n";

#define MAX_OPTS 16

typedef struct eopts {
    const char *input, *output, *format;
    lc_option opt[MAX_OPTS];
    int nopt;
    cli_load load; /* the input flags render takes (cli_input_flag) */
    const char *first[NKINDS];
    lc_rbf_encode_desc d;
    int text, quiet, progress, tty, threads;
} eopts;

static const char *cmd = "lanecast encode";

static int parse_opt(eopts *o, const char *v)
{
    const char *eq = strchr(v, '=');
    if (!eq || eq == v || o->nopt == MAX_OPTS) {
        fprintf(stderr, "%s: --opt: expected KEY=VALUE (at most %d), got '%s'\n", cmd, MAX_OPTS, v);
        return -1;
    }
    char *key = strndup(v, (size_t)(eq - v)); /* lives until exit */
    if (!key) return -1;
    o->opt[o->nopt++] = (lc_option){key, eq + 1};
    return 0;
}

/* The flags with a value: 1 consumed, 0 not one, -1 bad. */
static int parse_valued(eopts *o, int argc, char **argv, int *i)
{
    static const char *const flags[] = {"-o",          "--output",     "--max-error", "--max-rbfs", "--centre",
                                        "--center",    "--fit-range",  "--fit-samples", "--lm-samples",
                                        "--local-rbfs", "--seed",      "--threads",   "--format",   "--opt"};
    const char *a = argv[*i], *v;
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    int n;
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) return o->output = v, 1;
    if (!strcmp(a, "--format")) return o->format = v, 1;
    if (!strcmp(a, "--opt")) return parse_opt(o, v) ? -1 : 1;
    if (!strcmp(a, "--max-error")) {
        if (arg_float(cmd, a, v, 0.0f, 1.0f, &o->d.max_error)) return -1;
        if (!(o->d.max_error > 0.0f && o->d.max_error < 1.0f)) {
            fprintf(stderr, "%s: --max-error: %s is not in (0, 1)\n", cmd, v);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--max-rbfs")) return arg_size_t(cmd, a, v, &o->d.max_rbfs) ? -1 : 1;
    if (!strcmp(a, "--fit-samples")) return arg_size_t(cmd, a, v, &o->d.fit_samples) ? -1 : 1;
    if (!strcmp(a, "--lm-samples")) return arg_size_t(cmd, a, v, &o->d.lm_samples) ? -1 : 1;
    if (!strcmp(a, "--local-rbfs")) return arg_int(cmd, a, v, 1, 32, &o->d.local_rbfs) ? -1 : 1;
    if (!strcmp(a, "--seed")) return arg_int(cmd, a, v, 1, 2147483647, &n) ? -1 : (o->d.seed = (uint32_t)n, 1);
    if (!strcmp(a, "--threads")) return arg_int(cmd, a, v, 1, 1024, &o->threads) ? -1 : 1;
    if (!strcmp(a, "--fit-range")) {
        if (arg_pair(cmd, a, v, o->d.fit_range)) return -1;
        if (!(o->d.fit_range[0] <= o->d.fit_range[1])) {
            fprintf(stderr, "%s: --fit-range: expected LO <= HI, got '%s'\n", cmd, v);
            return -1;
        }
        return o->d.fit_range_set = 1, 1;
    }
    if (!strcmp(v, "mean")) o->d.centre = LC_RBF_CENTRE_MEAN; /* --centre */
    else if (!strcmp(v, "maxerr")) o->d.centre = LC_RBF_CENTRE_MAXERR;
    else {
        fprintf(stderr, "%s: %s: '%s' is not mean or maxerr\n", cmd, a, v);
        return -1;
    }
    return 1;
}

/* 0 ok, 1 help printed, -1 usage error. */
static int parse(eopts *o, int argc, char **argv)
{
    o->tty = isatty(2);
    o->progress = o->tty;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int r;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) return fputs(encode_help, stdout), 1;
        if (!strcmp(a, "--text")) o->text = 1;
        else if (!strcmp(a, "--quiet")) o->quiet = 1;
        else if (!strcmp(a, "--progress")) o->progress = 1;
        else if ((r = parse_valued(o, argc, argv, &i)) || (r = cli_input_flag(cmd, argc, argv, &i, &o->load, o->first))) {
            if (r < 0) return -1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", cmd, a, cmd);
            return -1;
        } else if (!o->input) {
            o->input = a;
        } else {
            fprintf(stderr, "%s: unexpected argument '%s'\n", cmd, a);
            return -1;
        }
    }
    if (!o->input) return fprintf(stderr, "%s: no input file (see %s --help)\n", cmd, cmd), -1;
    if (!o->output) return fprintf(stderr, "%s: no output: give -o OUT.rbf\n", cmd), -1;
    if (o->quiet) o->progress = 0;
    return 0;
}

static void progress(void *user, const lc_rbf_encode_progress *p)
{
    const eopts *o = user;
    if (p->polish) { /* the sweeps after max_rbfs: one line each */
        fprintf(stderr, "%sencode: %zu RBFs, polish sweep %d, RMS %.3f%% of the range (target %.3g%%), %.1f s\n",
                o->tty ? "\r" : "", p->rbfs, p->polish, 100.0 * p->rms, 100.0 * p->target, p->seconds);
        return;
    }
    if (!o->tty && (p->rbfs & (p->rbfs - 1))) return; /* redirected: powers of two only */
    fprintf(stderr, "%sencode: %zu RBFs (at most %zu), RMS %.3f%% of the range (target %.3g%%), %.1f s%s",
            o->tty ? "\r" : "", p->rbfs, p->max_rbfs, 100.0 * p->rms, 100.0 * p->target, p->seconds,
            o->tty ? "   " : "\n");
}

/* Fails early on a missing LAPACKE or an output folder that is not writable. */
static int preflight(const eopts *o)
{
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) == LC_OK && !strcmp(f.name, "lapacke") && !f.available) {
            fprintf(stderr, "%s: RBF encoding needs %s, which this build of lanecast lacks (install %s and rebuild)\n",
                    cmd, f.library, f.package);
            return -1;
        }
    }
    char *copy = strdup(o->output);
    int ok = copy && access(dirname(copy), W_OK) == 0;
    free(copy);
    if (!ok) fprintf(stderr, "%s: %s: its folder is not writable\n", cmd, o->output);
    return ok ? 0 : -1;
}

static void report(const eopts *o, const lc_samples_info *si, const lc_rbf_encode_report *r, uint64_t out_bytes,
                   double load_s, double write_s)
{
    printf("wrote %s (%s, %zu RBFs, %llu bytes)\n", o->output, o->text ? "text" : "binary", r->rbfs,
           (unsigned long long)out_bytes);
    printf("samples      %zu (%zu in the fit range %g..%g)\n", r->samples, r->fitted, (double)r->range[0],
           (double)r->range[1]);
    printf("rbfs         %zu, %d iterations; target RMS %.3g%%: %s\n", r->rbfs, r->iterations,
           100.0 * (o->d.max_error > 0.0f ? o->d.max_error : 0.02), r->reached ? "reached" : "NOT reached");
    printf("error        RMS %.4f%%, max %.3f%% of the value range\n", 100.0 * r->rms, 100.0 * r->max_error);
    uint64_t binary = 32 + 20 * (uint64_t)r->rbfs;
    printf("compression  %llu input bytes (%s) / %llu bytes (binary .rbf) = %.1f : 1\n",
           (unsigned long long)si->input_bytes, si->grid ? "voxels" : "x y z value as float32",
           (unsigned long long)binary, (double)si->input_bytes / (double)binary);
    printf("time         %.2f s (load %.2f s, encode %.2f s, write %.2f s)\n", load_s + r->seconds + write_s, load_s,
           r->seconds, write_s);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int cli_encode(int argc, char **argv)
{
    eopts o;
    memset(&o, 0, sizeof o);
    int p = parse(&o, argc, argv);
    if (p) return p > 0 ? 0 : CLI_EXIT_USAGE;
    if (preflight(&o)) return CLI_EXIT_FAIL;
    lc_device *dev = NULL;
    lc_samples *sm = NULL;
    lc_rbf_encoded *set = NULL;
    lc_device_desc dd = {.threads = o.threads};
    lc_status s = lc_device_create(&dd, &dev);
    double t0 = now();
    if (s == LC_OK) {
        lc_option all[CLI_MAX_OPTIONS + MAX_OPTS];
        int nall = cli_input_merge(cmd, &o.load, o.opt, o.nopt, all, CLI_MAX_OPTIONS + MAX_OPTS);
        if (nall < 0) {
            lc_device_destroy(dev);
            return CLI_EXIT_USAGE;
        }
        lc_load_desc ld = {.format = o.format ? o.format : o.load.format, .options = all, .noptions = nall};
        s = lc_samples_load(dev, o.input, &ld, &sm);
    }
    double load_s = now() - t0;
    lc_rbf_encode_report rep;
    if (s == LC_OK) {
        if (o.progress) o.d.progress = progress, o.d.progress_user = &o;
        s = lc_rbf_encode(dev, sm, &o.d, &set, &rep);
        if (o.progress && o.tty) fputc('\n', stderr);
    }
    double t1 = now();
    if (s == LC_OK) s = lc_rbf_write(dev, o.output, &set->desc, o.text ? LC_RBF_FILE_TEXT : LC_RBF_FILE_BINARY);
    double write_s = now() - t1;
    int rc = 0;
    if (s != LC_OK) {
        fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
        rc = CLI_EXIT_FAIL;
    } else if (!o.quiet) {
        lc_samples_info si;
        lc_samples_get_info(sm, &si);
        FILE *f = fopen(o.output, "rb");
        long bytes = 0;
        if (f && !fseek(f, 0, SEEK_END)) bytes = ftell(f);
        if (f) fclose(f);
        report(&o, &si, &rep, (uint64_t)bytes, load_s, write_s);
    }
    lc_rbf_encoded_free(set);
    lc_samples_destroy(sm);
    lc_device_destroy(dev);
    return rc;
}
