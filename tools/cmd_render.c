/* lanecast render / lanecast demo: load (or generate) data, render, write.
 * Kind-neutral: the kinds' flags, defaults and stats come from their rows
 * (cli_kind.h); the kind is decided once, from the input file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "cli_kind.h"

static const char render_help[] =
    "usage: lanecast render INPUT -o OUT.png|.exr|.tif [options]\n"
    "       lanecast demo [-o OUT.png] [options]\n"
    "\n"
    "Volume ray casting of particle data (sums of truncated Gaussians, Knoll et al. 2014), of\n"
    "structured volumes (implicit min-max BVH, Knoll et al. 2011) and of RBF sets (Jang et al.\n"
    "2004); the kind follows INPUT.\n"
    "The image format follows the extension of OUT (any OpenImageIO writes; 8-bit for png/jpg,\n"
    "float for exr/tif). The file is written under a temporary name and renamed when complete.\n"
    "\n"
    "input: the format is decided by the file's magic bytes, then its extension (see the kind\n"
    "sections below for the formats and flags of each kind of data)\n"
    "  --frame N             read frame N (from 0) of a trajectory (lanecast info INPUT counts them)\n"
    "  --frames A:B[:S]      render frames A, A+S, ... before B (B omitted: to the end; S default 1)\n"
    "                        as an image sequence; -o then names each image with a printf-style\n"
    "                        frame number, e.g. -o out_%04d.png; the first error stops the sequence\n"
    "  --topology FILE       a companion file: the PSF topology of a DCD trajectory (default: the\n"
    "                        DCD's name with .psf, when it exists)\n"
    "  example: lanecast render adk.dcd --topology adk.psf --frames 0:98:10 -o adk_%02d.png\n"
    "  --dataset PATH        HDF5: render this dataset (3-D: a grid; N x 3: particle positions)\n"
    "                        instead of the PartTypeN groups of a snapshot\n"
    "  example: lanecast render sim.h5 --dataset /fields/density -o density.png\n"
    "\n"
    "camera (default: perspective, looking down -z at the data, framing it):\n"
    "  --size WxH            image size in pixels (default 1024x1024)\n"
    "  --eye x,y,z --at x,y,z --up x,y,z   view (up defaults to 0,1,0)\n"
    "  --fov DEG             vertical field of view (default 40)\n"
    "  --ortho HEIGHT        orthographic projection with this image-plane height (0 = frame the data)\n"
    "\n"
    "classification and sampling:\n"
    "  --tf FILE|PRESET      transfer function: SPEC.md JSON file, or heat, cool, gray, demo\n"
    "  --tau T               peak extinction per world unit of a preset (default: by kind, below)\n"
    "  --range LO,HI         value range mapped to [0, 1] (default: the TF's, else the data's)\n"
    "  --dt DT               sampling step in world units (default: by kind, below)\n"
    "  --mode M              dvr (emission-absorption; the default) or mip (maximum intensity\n"
    "                        projection through the TF's colours; e.g. --mode mip --tf gray)\n"
    "  --shade [MODE]        none, diffuse (the default when MODE is omitted) or phong\n"
    "  --alpha-stop A        early ray termination opacity in (0, 1] (default 0.97; 1 = never)\n"
    "  --background r,g,b    background colour (default 0,0,0)\n"
    "  --alpha               write an alpha channel instead of compositing the background\n"
    "\n"
    "execution:\n"
    "  --method M            how the kind walks its data (each kind's section below lists its methods)\n"
    "  --packet N            rays per packet side: 8 = 8x8 groups (default), 1 = lane-width packets\n"
    "  --target T            scalar, sse4, avx2, avx512, avx512_8 or auto (default auto; see lanecast\n"
    "                        targets); avx512_8 = AVX-512 instructions at 8 lanes, for width studies\n"
    "  --threads N           worker threads (default: all CPUs)\n"
    "  --tile N              tile side in pixels (default 32)\n"
    "  --stats               print load, build and render times and counters\n"
    "  --progress            show a progress line on stderr (default when stderr is a terminal)\n"
    "  --quiet               print nothing but errors\n"
    "\n"
    "examples: each kind's section below\n"
    "\n"
    "exit status: 0 ok, 1 bad input or failed work (one message on stderr), 2 bad usage\n";

/* The kinds the command line knows, one row each (cli_kind.h). */
static const cli_kind *const kinds[] = {&cli_particles, &cli_grid, &cli_rbf};
#define NKINDS ((int)(sizeof kinds / sizeof kinds[0]))

lc_status cli_demo_scene(lc_device *dev, lc_volume **out, lc_tf **tf); /* cli_particles.c */

typedef struct ropts {
    const char *cmd;
    const char *input, *output;
    cli_load load;
    const char *first_flag[NKINDS]; /* first flag of each kind given */
    lc_render_desc rd;
    int target_set;
    lc_target target;
    int threads;
    const char *tf;
    float tau;
    lc_vec3 background;
    int alpha, stats, quiet, progress;
    /* trajectories: --frame, or --frames first:end:step (end -1 = to the last) */
    int64_t frame, first, end, step;
    int seq;
    const char *topology;
} ropts;

const cli_kind *cli_kind_of(lc_kind kind)
{
    for (int k = 0; k < NKINDS; k++)
        if (kinds[k]->kind == kind) return kinds[k];
    return NULL;
}

int cli_load_add(cli_load *l, const char *cmd, const char *key, const char *value)
{
    for (int i = 0; i < l->n; i++) /* a repeated flag: the last one wins */
        if (!strcmp(l->opt[i].key, key)) {
            snprintf(l->val[i], sizeof l->val[i], "%s", value);
            return 0;
        }
    if (l->n == CLI_MAX_OPTIONS || strlen(value) >= sizeof l->val[0]) {
        fprintf(stderr, "%s: too many or too long load options (at '%s')\n", cmd, key);
        return -1;
    }
    snprintf(l->val[l->n], sizeof l->val[0], "%s", value);
    l->opt[l->n].key = key;
    l->opt[l->n].value = l->val[l->n];
    l->n++;
    return 0;
}

static int parse_method(ropts *o, const char *v)
{
    if (!strcmp(v, "coherent")) o->rd.method = LC_METHOD_COHERENT;
    else if (!strcmp(v, "direct")) o->rd.method = LC_METHOD_DIRECT;
    else if (!strcmp(v, "bvh")) o->rd.method = LC_METHOD_BVH;
    else if (!strcmp(v, "brute")) o->rd.method = LC_METHOD_BRUTE;
    else {
        fprintf(stderr, "%s: --method: '%s' is not coherent, direct, bvh or brute\n", o->cmd, v);
        return -1;
    }
    return 0;
}

/* The camera and image flags: 1 consumed, 0 not one, -1 bad value. */
static int parse_view(ropts *o, int argc, char **argv, int *i, int *camera_set)
{
    const char *a = argv[*i], *v;
    static const char *const flags[] = {"--size", "--eye", "--at", "--up", "--fov", "--ortho", "--background"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    lc_camera *c = &o->rd.camera;
    if (!strcmp(a, "--size")) return arg_size(o->cmd, a, v, &o->rd.width, &o->rd.height) ? -1 : 1;
    if (!strcmp(a, "--eye")) return *camera_set |= 1, arg_vec3(o->cmd, a, v, &c->eye) ? -1 : 1;
    if (!strcmp(a, "--at")) return *camera_set |= 2, arg_vec3(o->cmd, a, v, &c->at) ? -1 : 1;
    if (!strcmp(a, "--up")) return arg_vec3(o->cmd, a, v, &c->up) ? -1 : 1;
    if (!strcmp(a, "--fov")) return arg_float(o->cmd, a, v, 0.01f, 179.0f, &c->fovy) ? -1 : 1;
    if (!strcmp(a, "--background")) return arg_vec3(o->cmd, a, v, &o->background) ? -1 : 1;
    c->projection = LC_ORTHOGRAPHIC; /* --ortho */
    return arg_float(o->cmd, a, v, 0.0f, 1e30f, &c->height) ? -1 : 1;
}

/* Classification, sampling and execution flags: 1 consumed, 0 not one, -1 bad. */
static int parse_render(ropts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--shade")) {
        o->rd.shading = LC_SHADE_DIFFUSE;
        if (*i + 1 < argc && argv[*i + 1][0] != '-') {
            const char *m = argv[*i + 1];
            if (!strcmp(m, "none")) o->rd.shading = LC_SHADE_NONE, ++*i;
            else if (!strcmp(m, "diffuse")) o->rd.shading = LC_SHADE_DIFFUSE, ++*i;
            else if (!strcmp(m, "phong")) o->rd.shading = LC_SHADE_PHONG, ++*i;
        }
        return 1;
    }
    static const char *const flags[] = {"--tf",     "--tau",    "--range",  "--dt",      "--alpha-stop", "--method",
                                        "--packet", "--target", "--threads", "--tile",   "--mode"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--tf")) return o->tf = v, 1;
    if (!strcmp(a, "--tau")) return arg_float(o->cmd, a, v, 0.0f, 1e30f, &o->tau) ? -1 : 1;
    if (!strcmp(a, "--range")) {
        if (arg_pair(o->cmd, a, v, o->rd.range)) return -1;
        if (!(o->rd.range[1] > o->rd.range[0])) {
            fprintf(stderr, "%s: --range: expected LO < HI, got '%s'\n", o->cmd, v);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--dt")) return arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->rd.dt) ? -1 : 1;
    if (!strcmp(a, "--alpha-stop")) return arg_float(o->cmd, a, v, 1e-6f, 1.0f, &o->rd.alpha_stop) ? -1 : 1;
    if (!strcmp(a, "--method")) return parse_method(o, v) ? -1 : 1;
    if (!strcmp(a, "--packet")) return arg_int(o->cmd, a, v, 1, 64, &o->rd.packet) ? -1 : 1;
    if (!strcmp(a, "--threads")) return arg_int(o->cmd, a, v, 1, 1024, &o->threads) ? -1 : 1;
    if (!strcmp(a, "--tile")) return arg_int(o->cmd, a, v, 1, 4096, &o->rd.tile) ? -1 : 1;
    if (!strcmp(a, "--mode")) {
        if (!strcmp(v, "dvr")) o->rd.mode = LC_MODE_DVR;
        else if (!strcmp(v, "mip")) o->rd.mode = LC_MODE_MIP;
        else {
            fprintf(stderr, "%s: --mode: '%s' is not a render mode (dvr, mip)\n", o->cmd, v);
            return -1;
        }
        return 1;
    }
    if (lc_target_from_name(v, &o->target) != LC_OK) { /* --target */
        fprintf(stderr, "%s: --target: %s\n", o->cmd, lc_last_error());
        return -1;
    }
    o->target_set = 1;
    return 1;
}

/* The input flags --frame, --frames, --topology and --dataset: 1 consumed, 0 not one, -1 bad. */
static int parse_input(ropts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (strcmp(a, "--frame") && strcmp(a, "--frames") && strcmp(a, "--topology") && strcmp(a, "--dataset")) return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--topology")) return o->topology = v, 1;
    if (!strcmp(a, "--dataset")) return cli_load_add(&o->load, o->cmd, "dataset", v) ? -1 : 1;
    char *end;
    if (!strcmp(a, "--frame")) {
        long long f = strtoll(v, &end, 10);
        if (end == v || *end || f < 0) {
            fprintf(stderr, "%s: --frame: '%s' is not a frame number (0, 1, ...)\n", o->cmd, v);
            return -1;
        }
        return o->frame = f, 1;
    }
    long long x[3] = {0, -1, 1};
    const char *p = v;
    for (int k = 0; k < 3; k++) {
        if (k == 1 && *p == ':' && (p[1] == '\0' || p[1] == ':')) { /* A: or A::S = to the end */
            if (!*++p) break;
            continue;
        }
        if (k > 0 && *p++ != ':') goto bad;
        x[k] = strtoll(p, &end, 10);
        if (end == p || x[k] < 0) goto bad;
        p = end;
        if (!*p) break;
    }
    if (*p || x[2] < 1 || (x[1] >= 0 && x[1] <= x[0])) goto bad;
    o->first = x[0], o->end = x[1], o->step = x[2], o->seq = 1;
    return 1;
bad:
    fprintf(stderr, "%s: --frames: '%s' is not A:B[:S] with 0 <= A < B (B may be empty: to the end) and S >= 1\n",
            o->cmd, v);
    return -1;
}

/* Checks an image-sequence name: exactly one %d conversion (flags 0 and a
 * width allowed), other percent signs doubled. */
static int sequence_name_ok(const char *name)
{
    int n = 0;
    for (const char *p = name; *p; p++) {
        if (*p != '%') continue;
        if (p[1] == '%') {
            p++;
            continue;
        }
        p++;
        while (*p == '0') p++;
        while (*p >= '0' && *p <= '9') p++;
        if (*p != 'd') return 0;
        n++;
    }
    return n == 1;
}

static void frame_name(const char *pattern, int64_t f, char *out, size_t n)
{
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    snprintf(out, n, pattern, (int)f); /* checked by sequence_name_ok */
#pragma GCC diagnostic pop
}

static void print_help(void)
{
    fputs(render_help, stdout);
    for (int k = 0; k < NKINDS; k++) fputs(kinds[k]->help, stdout);
}

/* Returns 0 ok, 1 help printed, -1 usage error (message printed). */
static int parse(ropts *o, int argc, char **argv, int want_input)
{
    o->rd.width = o->rd.height = 1024;
    o->progress = isatty(2);
    int camera_set = 0, r = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) return print_help(), 1;
        if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            if (!(o->output = arg_value(o->cmd, argc, argv, &i))) return -1;
            continue;
        }
        if (!strcmp(a, "--alpha")) o->alpha = 1;
        else if (!strcmp(a, "--stats")) o->stats = 1;
        else if (!strcmp(a, "--progress")) o->progress = 1;
        else if (!strcmp(a, "--quiet")) o->quiet = 1;
        else if ((r = parse_view(o, argc, argv, &i, &camera_set)) || (r = parse_render(o, argc, argv, &i)) ||
                 (want_input && (r = parse_input(o, argc, argv, &i)))) {
            if (r < 0) return -1;
        } else {
            for (int k = 0; k < NKINDS && !r; k++)
                r = kinds[k]->parse_flag(o->cmd, argc, argv, &i, &o->load, &o->first_flag[k]);
            if (r < 0) return -1;
            if (r) continue;
            if (a[0] == '-' && a[1]) {
                fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", o->cmd, a, o->cmd);
                return -1;
            } else if (want_input && !o->input) {
                o->input = a;
            } else {
                fprintf(stderr, "%s: unexpected argument '%s'\n", o->cmd, a);
                return -1;
            }
        }
    }
    if (camera_set && camera_set != 3) {
        fprintf(stderr, "%s: give both --eye and --at (or neither, to frame the data)\n", o->cmd);
        return -1;
    }
    if (want_input && !o->input) {
        fprintf(stderr, "%s: no input file (see %s --help)\n", o->cmd, o->cmd);
        return -1;
    }
    if (!o->output) {
        fprintf(stderr, "%s: no output image: give -o OUT.png\n", o->cmd);
        return -1;
    }
    if (o->seq && o->frame) {
        fprintf(stderr, "%s: give --frame or --frames, not both\n", o->cmd);
        return -1;
    }
    if (o->seq && !sequence_name_ok(o->output)) {
        fprintf(stderr, "%s: --frames needs an output name with one frame number in it, e.g. -o out_%%04d.png "
                "(got '%s')\n", o->cmd, o->output);
        return -1;
    }
    if (o->seq && o->end >= 0 && (o->end - o->first + o->step - 1) / o->step > 1000000) {
        fprintf(stderr, "%s: --frames: more than a million images\n", o->cmd);
        return -1;
    }
    if (o->quiet) o->progress = 0;
    return 0;
}

static void progress(void *user, float f)
{
    (void)user;
    fprintf(stderr, "\rrendering %3d%%", (int)(100.0f * f + 0.5f));
    if (f >= 1.0f) fputc('\n', stderr);
}

/* The kind of the input, decided once through the formats registry; flags of
 * another kind are an error (they would be ignored). Returns the row or NULL
 * (message printed; *usage set when the flags were at fault). */
static const cli_kind *decide_kind(ropts *o, lc_device *dev, lc_kind forced, int *usage, int64_t *frames)
{
    lc_kind kind = forced;
    *frames = 1;
    if (kind == LC_KIND_NONE) {
        lc_file_info fi;
        /* the options too: a container's kind may depend on them (HDF5 --dataset) */
        lc_load_desc ld = {.format = o->load.format, .companion = o->topology, .options = o->load.opt,
                           .noptions = o->load.n};
        if (lc_file_probe(dev, o->input, &ld, &fi) != LC_OK) {
            fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
            return NULL;
        }
        kind = fi.kind;
        *frames = fi.frames;
    }
    const cli_kind *row = NULL;
    for (int k = 0; k < NKINDS; k++)
        if (kinds[k]->kind == kind) row = kinds[k];
    for (int k = 0; k < NKINDS && row; k++)
        if (kinds[k] != row && o->first_flag[k]) {
            fprintf(stderr, "%s: %s does not apply to %s input (%s)\n", o->cmd, o->first_flag[k], lc_kind_name(kind),
                    o->input ? o->input : "the demo");
            *usage = 1;
            return NULL;
        }
    if (!row) fprintf(stderr, "%s: no command-line support for %s data\n", o->cmd, lc_kind_name(kind));
    return row;
}

static double seconds_since(const struct timespec *t0)
{
    struct timespec t1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (double)(t1.tv_sec - t0->tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0->tv_nsec);
}

static void print_stats(const ropts *o, const cli_kind *kind, const lc_volume *vol, double load_s,
                        const lc_render_stats *st)
{
    double t = st->seconds;
    printf("target        %s (%d lanes), %d threads\n", lc_target_name(st->target), lc_target_lanes(st->target),
           st->threads);
    kind->print_stats(vol, load_s, stdout);
    printf("render        %.3f s (%.2f fps)\n", t, 1.0 / t);
    printf("rays          %llu\n", (unsigned long long)st->rays);
    printf("samples       %llu\n", (unsigned long long)st->samples);
    printf("%s %llu (%.1f M/s)\n", kind->evals, (unsigned long long)st->kernel_evals, (double)st->kernel_evals / t / 1e6);
    printf("nodes         %llu, leaves %llu, passes %llu\n", (unsigned long long)st->nodes,
           (unsigned long long)st->leaves, (unsigned long long)st->passes);
    (void)o;
}

/* Loads (or makes) the volume and its TF. */
static lc_status load(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t frame, lc_volume **vol,
                      lc_tf **tf)
{
    lc_status s;
    if (demo) {
        s = cli_demo_scene(dev, vol, o->tf ? NULL : tf);
    } else {
        lc_load_desc ld = {.format = o->load.format, .companion = o->topology, .frame = frame,
                           .options = o->load.opt, .noptions = o->load.n};
        s = lc_volume_load(dev, o->input, &ld, vol);
    }
    if (s != LC_OK) return s;
    s = kind->apply(*vol, &o->rd);
    if (s != LC_OK || *tf) return s;
    if (o->tf && (strchr(o->tf, '.') || strchr(o->tf, '/'))) return lc_tf_load(dev, o->tf, tf);
    return kind->default_tf(dev, *vol, o->tf, o->tau, tf);
}

/* Warnings (a missing topology, ...) on stderr; errors are printed by the caller. */
static void log_warning(void *user, lc_log_level level, const char *msg)
{
    static char last[1024]; /* once per sequence, not once per frame */
    if (level != LC_LOG_WARNING || !strncmp(last, msg, sizeof last - 1)) return;
    snprintf(last, sizeof last, "%s", msg);
    fprintf(stderr, "%s: warning: %s\n", (const char *)user, msg);
}

/* Loads frame f, renders it and writes it to out. */
static lc_status render_one(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t f, const char *out,
                            lc_tf **tf, float *rgba)
{
    lc_volume *vol = NULL;
    struct timespec ts0;
    clock_gettime(CLOCK_MONOTONIC, &ts0);
    lc_status s = load(o, dev, demo, kind, f, &vol, tf);
    if (s == LC_OK) {
        double load_s = seconds_since(&ts0);
        o->rd.volume = vol;
        o->rd.tf = *tf;
        lc_render_stats st;
        s = lc_render(dev, &o->rd, rgba, &st);
        lc_image_desc id = {o->rd.width, o->rd.height, rgba, o->background, o->alpha};
        if (s == LC_OK) s = lc_image_write(dev, out, &id);
        if (s == LC_OK && !o->quiet) printf("wrote %s (%dx%d)\n", out, o->rd.width, o->rd.height);
        if (s == LC_OK && o->stats) print_stats(o, kind, vol, load_s, &st);
    }
    o->rd.volume = NULL;
    lc_volume_destroy(vol);
    return s;
}

static int run(ropts *o, int demo)
{
    int rc = CLI_EXIT_FAIL, usage = 0;
    lc_device *dev = NULL;
    lc_tf *tf = NULL;
    float *rgba = NULL;
    char out[4096];
    snprintf(out, sizeof out, "%s", o->output);
    if (o->seq) frame_name(o->output, o->first, out, sizeof out);
    /* fail on an unwritable output before any long work */
    if (lc_image_check(NULL, out) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    lc_device_desc dd = {.target = o->target_set ? o->target : LC_TARGET_AUTO, .threads = o->threads,
                         .log = o->quiet ? NULL : log_warning, .log_user = (void *)o->cmd};
    if (lc_device_create(&dd, &dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    int64_t frames = 1;
    const cli_kind *kind = decide_kind(o, dev, demo ? LC_KIND_PARTICLES : LC_KIND_NONE, &usage, &frames);
    if (!kind) {
        lc_device_destroy(dev);
        return usage ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
    }
    /* the frames to render: one, or first, first + step, ... before end */
    int64_t first = o->seq ? o->first : o->frame, end = o->seq ? o->end : o->frame + 1, step = o->seq ? o->step : 1;
    if (end < 0) end = frames; /* "A:" = to the last frame (0 frames = could not count: the load says why) */
    if (frames > 0 && (first >= frames || (o->seq && end > frames))) {
        char asked[64];
        if (o->seq) snprintf(asked, sizeof asked, "frames %lld:%lld", (long long)first, (long long)end);
        else snprintf(asked, sizeof asked, "frame %lld", (long long)first);
        fprintf(stderr, "%s: %s holds %lld frame%s (0 to %lld); %s was asked for\n", o->cmd, o->input,
                (long long)frames, frames == 1 ? "" : "s", (long long)frames - 1, asked);
        lc_device_destroy(dev);
        return CLI_EXIT_FAIL;
    }
    if (frames == 0 && end <= first) end = first + 1; /* uncounted: try, and let the load say why */
    if (demo && o->rd.shading == LC_SHADE_NONE) o->rd.shading = LC_SHADE_PHONG;
    if (o->progress) o->rd.progress = progress;
    rgba = malloc(sizeof(float) * 4 * (size_t)o->rd.width * (size_t)o->rd.height);
    if (!rgba) {
        fprintf(stderr, "%s: out of memory for a %dx%d image\n", o->cmd, o->rd.width, o->rd.height);
        goto out;
    }
    for (int64_t f = first; f < end; f += step) {
        if (o->seq) frame_name(o->output, f, out, sizeof out);
        if (render_one(o, dev, demo, kind, f, out, &tf, rgba) != LC_OK) {
            if (o->seq)
                fprintf(stderr, "%s: frame %lld (%s): %s; the sequence stops here\n", o->cmd, (long long)f, out,
                        lc_last_error());
            else
                fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
            goto out;
        }
    }
    rc = 0;
out:
    free(rgba);
    lc_tf_destroy(tf);
    lc_device_destroy(dev);
    return rc;
}

int cli_render(int argc, char **argv)
{
    ropts o;
    memset(&o, 0, sizeof o);
    o.cmd = "lanecast render";
    int p = parse(&o, argc, argv, 1);
    if (p) return p > 0 ? 0 : CLI_EXIT_USAGE;
    return run(&o, 0);
}

int cli_demo(int argc, char **argv)
{
    ropts o;
    memset(&o, 0, sizeof o);
    o.cmd = "lanecast demo";
    o.output = "lanecast-demo.png";
    int p = parse(&o, argc, argv, 0);
    if (p) return p > 0 ? 0 : CLI_EXIT_USAGE;
    return run(&o, 1);
}
