/* lanecast resample INPUT -o GRID.nrrd --dims N[,N,N]: a particle set's
 * field deposited at the nodes of a grid (lc_particles_resample) and written
 * as a volume (lc_volume_write); and the deposit behind lanecast render
 * --resample N (cli_resample_grid). Public calls only. */
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "progress.h"
#include "render_opts.h"

static const char resample_help[] =
    "usage: lanecast resample INPUT -o GRID.nrrd --dims N[,N,N] [options]\n"
    "\n"
    "Deposits a particle set's field at the nodes of a grid and writes the grid as a volume, which\n"
    "lanecast render (and any NRRD reader) takes. The value at a node is what the particle\n"
    "renderer evaluates at that point: the Gaussian kappa k exp(-d^2 / (2 r^2)) cut at sigma r, or\n"
    "the SPH kernel of --kernel with support H = r, with the weights the loader made (--value A\n"
    "with an SPH kernel: m/rho A). Rendering the grid approximates the particle image at the frame\n"
    "rate of a grid (lanecast render --resample N does both in one run; docs/BENCHMARKS.md gives\n"
    "the error against the exact image).\n"
    "\n"
    "grid:\n"
    "  -o GRID               .nrrd (header and data in one file) or .nhdr (a detached header and\n"
    "                        its data in GRID.raw beside it); written under a temporary name and\n"
    "                        renamed when complete\n"
    "  --dims N[,N,N]        nodes per axis, 1 to 16777216 (one number: N on every axis); required\n"
    "  --box X0,Y0,Z0,X1,Y1,Z1  the grid's first and last node (default: the particles' bounds\n"
    "                        grown by their support, where the renderer samples them); an axis of\n"
    "                        one node lies at the box's centre. Particles outside still add what\n"
    "                        their support reaches inside it\n"
    "  --field N|all         the field deposited (default all: the sum of every field)\n"
    "  --type f32|u8|u16     the stored type (default f32); u8 and u16 store\n"
    "                        round((v - lo) / (hi - lo) * 255 or 65535), clamped\n"
    "  --range LO,HI         u8 and u16: the values mapped to 0 and the top (default: the grid's\n"
    "                        minimum and maximum); recorded as the header's old min / old max\n"
    "  --max-memory SIZE     refuse (before allocating) a grid whose values, particle lists and\n"
    "                        scratch need more than SIZE, e.g. 2G (default 3/4 of the physical\n"
    "                        memory); also the limit of loading INPUT\n"
    "\n"
    "input: every particle flag of lanecast render, as render takes it: --raw-particles N,\n"
    "  --radius, --radius-scale, --value, --select, --field-by, --types, --knn, --kernel, --hsml-is,\n"
    "  --sigma, --kappa, --frame N, --topology FILE, --format NAME, --option KEY=VALUE\n"
    "\n"
    "run:\n"
    "  --threads N           worker threads (default: all CPUs); the values do not depend on it\n"
    "  --target NAME         SIMD target: scalar, sse4, avx2, avx512, avx512_8, auto (default)\n"
    "  --progress            a progress bar on stderr for work over a second (default when stderr\n"
    "                        is a terminal)\n"
    "  --quiet               print nothing but errors\n"
    "\n"
    "examples:\n"
    "  lanecast resample 1tw7_solvated.pdb -o 1tw7.nrrd --dims 256\n"
    "  lanecast resample snap.dat --types 0 --kernel m4 --value rho -o rho.nhdr --dims 512 --type u16\n"
    "  lanecast resample atoms.f32 --raw-particles 1000000 --radius 0.5 -o a.nrrd --dims 128,128,64 \\\n"
    "      --box 0,0,0,100,100,50\n"
    "  lanecast render 1tw7.nrrd -o grid.png --range 0,1   (the grid; or: lanecast render\n"
    "      1tw7_solvated.pdb --resample 256 -o grid.png)\n"
    "\n"
    "exit status: 0 ok, 1 bad input or failed work (one message on stderr, nothing written),\n"
    "2 bad usage\n";

typedef struct qopts {
    const char *input, *output, *topology, *format;
    cli_load load;
    const char *first[NKINDS];
    lc_option opt[CLI_MAX_OPTIONS];
    char keys[CLI_MAX_OPTIONS][96];
    int nopt;
    long long frame;
    lc_resample_desc d;
    lc_value_type type;
    float range[2];
    int range_set, threads, quiet, progress, target_set;
    lc_target target;
} qopts;

static int parse_dims(const char *cmd, const char *v, int size[3])
{
    long long n[3];
    if (!strchr(v, ',')) {
        if (arg_ints(cmd, "--dims", v, 1, 1, 1 << 24, n)) return -1;
        size[0] = size[1] = size[2] = (int)n[0];
        return 0;
    }
    if (arg_ints(cmd, "--dims", v, 3, 1, 1 << 24, n)) return -1;
    for (int a = 0; a < 3; a++) size[a] = (int)n[a];
    return 0;
}

static int parse_box(const char *cmd, const char *v, lc_box3 *box)
{
    float f[6];
    const char *p = v;
    for (int k = 0; k < 6; k++) {
        char *end;
        f[k] = strtof(p, &end);
        if (end == p || (k < 5 ? *end != ',' : *end != '\0') || !(f[k] - f[k] == 0.0f)) {
            fprintf(stderr, "%s: --box: expected six numbers X0,Y0,Z0,X1,Y1,Z1, got '%s'\n", cmd, v);
            return -1;
        }
        p = end + 1;
    }
    for (int a = 0; a < 3; a++)
        if (f[a + 3] < f[a]) {
            fprintf(stderr, "%s: --box: the last node's %c (%g) lies below the first's (%g)\n", cmd, 'x' + a,
                    (double)f[a + 3], (double)f[a]);
            return -1;
        }
    *box = (lc_box3){{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
    return 0;
}

/* One of resample's own flags: 1 consumed, 0 not one, -1 bad (message printed). */
static int own_flag(qopts *o, const char *cmd, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    static const char *const valued[] = {"-o", "--output", "--dims", "--box", "--field", "--type", "--range",
                                         "--max-memory", "--threads", "--target", "--frame", "--topology",
                                         "--format", "--option"};
    int known = 0;
    for (size_t k = 0; k < sizeof valued / sizeof valued[0]; k++) known |= !strcmp(a, valued[k]);
    if (!known) return 0;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "-o") || !strcmp(a, "--output")) return o->output = v, 1;
    if (!strcmp(a, "--dims")) return parse_dims(cmd, v, o->d.size) ? -1 : 1;
    if (!strcmp(a, "--box")) return parse_box(cmd, v, &o->d.box) ? -1 : 1;
    if (!strcmp(a, "--field")) {
        if (!strcmp(v, "all")) return o->d.field = -1, 1;
        return arg_int(cmd, a, v, 0, LC_MAX_FIELDS - 1, &o->d.field) ? -1 : 1;
    }
    if (!strcmp(a, "--type")) {
        static const struct { const char *name; lc_value_type t; } types[] = {
            {"f32", LC_VALUE_FLOAT32}, {"float32", LC_VALUE_FLOAT32}, {"float", LC_VALUE_FLOAT32},
            {"u8", LC_VALUE_UINT8},    {"uint8", LC_VALUE_UINT8},     {"u16", LC_VALUE_UINT16},
            {"uint16", LC_VALUE_UINT16}};
        for (size_t k = 0; k < sizeof types / sizeof types[0]; k++)
            if (!strcmp(v, types[k].name)) return o->type = types[k].t, 1;
        fprintf(stderr, "%s: --type: '%s' is not f32, u8 or u16\n", cmd, v);
        return -1;
    }
    if (!strcmp(a, "--range")) {
        if (arg_pair(cmd, a, v, o->range)) return -1;
        if (!(o->range[1] > o->range[0])) {
            fprintf(stderr, "%s: --range: '%s': expected LO,HI with LO < HI\n", cmd, v);
            return -1;
        }
        return o->range_set = 1, 1;
    }
    if (!strcmp(a, "--max-memory"))
        return arg_memory_bytes(cmd, a, v, &o->d.max_memory) || cli_load_add(&o->load, cmd, "max_memory", v) ? -1 : 1;
    if (!strcmp(a, "--threads")) return arg_int(cmd, a, v, 1, 1024, &o->threads) ? -1 : 1;
    if (!strcmp(a, "--target")) {
        if (lc_target_from_name(v, &o->target) != LC_OK) {
            fprintf(stderr, "%s: --target: '%s' is not a target (scalar, sse4, avx2, avx512, avx512_8, auto)\n", cmd, v);
            return -1;
        }
        return o->target_set = 1, 1;
    }
    if (!strcmp(a, "--frame")) {
        char *end;
        o->frame = strtoll(v, &end, 10);
        if (end == v || *end || o->frame < 0) {
            fprintf(stderr, "%s: --frame: '%s' is not a frame number (0, 1, ...)\n", cmd, v);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--topology")) return o->topology = v, 1;
    if (!strcmp(a, "--format")) return o->format = v, 1;
    const char *eq = strchr(v, '='); /* --option KEY=VALUE */
    if (!eq || eq == v || o->nopt == CLI_MAX_OPTIONS || (size_t)(eq - v) >= sizeof o->keys[0]) {
        fprintf(stderr, "%s: --option: expected KEY=VALUE, got '%s'\n", cmd, v);
        return -1;
    }
    snprintf(o->keys[o->nopt], sizeof o->keys[0], "%.*s", (int)(eq - v), v);
    o->opt[o->nopt].key = o->keys[o->nopt], o->opt[o->nopt].value = eq + 1;
    o->nopt++;
    return 1;
}

static int parse(qopts *o, const char *cmd, int argc, char **argv)
{
    o->progress = isatty(2);
    o->d.field = -1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) return fputs(resample_help, stdout), 1;
        int r;
        if (!strcmp(a, "--quiet")) o->quiet = 1;
        else if (!strcmp(a, "--progress")) o->progress = 1;
        else if ((r = own_flag(o, cmd, argc, argv, &i)) || (r = cli_input_flag(cmd, argc, argv, &i, &o->load, o->first))) {
            if (r < 0) return -1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", cmd, a, cmd);
            return -1;
        } else if (!o->input) {
            o->input = a;
        } else {
            fprintf(stderr, "%s: one input file, got '%s' after '%s'\n", cmd, a, o->input);
            return -1;
        }
    }
    for (int k = 0; k < NKINDS; k++)
        if (o->first[k] && cli_kinds[k]->kind != LC_KIND_PARTICLES) {
            fprintf(stderr, "%s: %s does not apply: resample takes particle data\n", cmd, o->first[k]);
            return -1;
        }
    const char *ext = o->output ? strrchr(o->output, '.') : NULL;
    const char *why = !o->input ? "no input file" : !o->output ? "no output grid: give -o GRID.nrrd"
                      : !o->d.size[0] ? "no grid size: give --dims N or --dims NX,NY,NZ"
                      : !ext || (strcasecmp(ext, ".nrrd") && strcasecmp(ext, ".nhdr")) ? "-o: the grid is written as .nrrd or .nhdr"
                      : o->range_set && o->type != LC_VALUE_UINT8 && o->type != LC_VALUE_UINT16
                          ? "--range applies to --type u8 and u16 (float32 stores the values)"
                          : NULL;
    if (why) {
        fprintf(stderr, "%s: %s (see %s --help)\n", cmd, why, cmd);
        return -1;
    }
    if (o->quiet) o->progress = 0;
    return 0;
}

/* The output's folder must be writable before any long work. */
static int writable(const char *cmd, const char *path)
{
    char *copy = strdup(path);
    int ok = copy && access(dirname(copy), W_OK) == 0;
    free(copy);
    if (!ok) fprintf(stderr, "%s: %s: its folder is not writable (or does not exist)\n", cmd, path);
    return ok;
}

static void log_warning(void *user, lc_log_level level, const char *msg)
{
    if (level == LC_LOG_WARNING) fprintf(stderr, "%s: warning: %s\n", (const char *)user, msg);
}

/* Loads the particles (no other kind) and applies the particle flags. */
static lc_status load(qopts *o, const char *cmd, lc_device *dev, lc_volume **vol)
{
    lc_option all[2 * CLI_MAX_OPTIONS];
    int nall = cli_input_merge(cmd, &o->load, o->opt, o->nopt, all, 2 * CLI_MAX_OPTIONS);
    if (nall < 0) return LC_ERROR_INVALID_ARGUMENT;
    lc_load_desc ld = {.format = o->format ? o->format : o->load.format, .companion = o->topology, .frame = o->frame,
                       .options = all, .noptions = nall};
    lc_file_info fi;
    if (lc_file_probe(dev, o->input, &ld, &fi) != LC_OK) return fprintf(stderr, "%s: %s\n", cmd, lc_last_error()), LC_ERROR_IO;
    if (fi.kind != LC_KIND_PARTICLES) {
        fprintf(stderr, "%s: %s holds %s data (%s); resample takes particle data\n", cmd, o->input,
                lc_kind_name(fi.kind), fi.format);
        return LC_ERROR_INVALID_ARGUMENT;
    }
    load_ticker tk;
    ticker_start(&tk, o->input, o->progress);
    ld.progress = tk.started ? load_progress : NULL, ld.progress_user = &tk;
    lc_status s = lc_volume_load(dev, o->input, &ld, vol);
    ticker_stop(&tk);
    lc_render_desc rd = {0};
    if (s == LC_OK) s = cli_kind_of(LC_KIND_PARTICLES)->apply(*vol, &rd);
    if (s != LC_OK) fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
    return s;
}

lc_status cli_resample_values(const char *cmd, lc_device *dev, const lc_volume *particles, const lc_resample_desc *d,
                              int progress, float **values, lc_resample_info *info)
{
    *values = NULL;
    lc_status s = lc_particles_resample(dev, particles, d, NULL, info); /* the sizes, before allocating */
    if (s != LC_OK) return fprintf(stderr, "%s: %s\n", cmd, lc_last_error()), s;
    size_t n = (size_t)d->size[0] * (size_t)d->size[1] * (size_t)d->size[2];
    *values = malloc(sizeof(float) * n);
    if (!*values) {
        fprintf(stderr, "%s: out of memory for %zu grid values\n", cmd, n);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    progress_state ps = {"depositing", now_seconds(), 0};
    lc_resample_desc dd = *d;
    if (progress) dd.progress = render_progress, dd.progress_user = &ps;
    s = lc_particles_resample(dev, particles, &dd, *values, info);
    progress_clear(&ps);
    if (s != LC_OK) {
        fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
        free(*values), *values = NULL;
    }
    return s;
}

int cli_resample(int argc, char **argv)
{
    const char *cmd = "lanecast resample";
    static qopts o; /* static: the load options' values outlive parsing */
    memset(&o, 0, sizeof o);
    int p = parse(&o, cmd, argc, argv);
    if (p) return p > 0 ? 0 : CLI_EXIT_USAGE;
    if (!writable(cmd, o.output)) return CLI_EXIT_FAIL;
    lc_device *dev = NULL;
    lc_device_desc dd = {.target = o.target_set ? o.target : LC_TARGET_AUTO, .threads = o.threads,
                         .log = o.quiet ? NULL : log_warning, .log_user = (void *)cmd};
    if (lc_device_create(&dd, &dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    lc_volume *vol = NULL;
    float *values = NULL;
    int rc = CLI_EXIT_FAIL;
    if (load(&o, cmd, dev, &vol) != LC_OK) goto out;
    lc_resample_info info;
    if (cli_resample_values(cmd, dev, vol, &o.d, o.progress, &values, &info) != LC_OK) goto out;
    lc_volume_write_desc wd = {.size = {o.d.size[0], o.d.size[1], o.d.size[2]}, .values = values,
                               .origin = info.origin, .spacing = info.spacing, .type = o.type,
                               .range = {o.range[0], o.range[1]}};
    if (lc_volume_write(dev, o.output, &wd) != LC_OK) {
        fprintf(stderr, "%s: %s\n", cmd, lc_last_error());
        goto out;
    }
    if (!o.quiet) {
        const char *tn = o.type == LC_VALUE_UINT8 ? "uint8" : o.type == LC_VALUE_UINT16 ? "uint16" : "float32";
        printf("wrote %s (%dx%dx%d %s)\n", o.output, o.d.size[0], o.d.size[1], o.d.size[2], tn);
        printf("origin        %g %g %g\nspacing       %g %g %g\n", (double)info.origin.x, (double)info.origin.y,
               (double)info.origin.z, (double)info.spacing.x, (double)info.spacing.y, (double)info.spacing.z);
        printf("values        %g .. %g\n", (double)info.value_min, (double)info.value_max);
        lc_target t;
        lc_device_target(dev, &t);
        printf("deposit       %.3f s, %d threads, %s; %llu terms, %d bricks, %llu particle-brick entries, %.1f MiB\n",
               info.seconds, info.threads, lc_target_name(t), (unsigned long long)info.evaluations, info.bricks,
               (unsigned long long)info.entries, (double)info.bytes / 1048576.0);
    }
    rc = 0;
out:
    free(values);
    lc_volume_destroy(vol);
    lc_device_destroy(dev);
    return rc;
}
