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
    "  --mode M              dvr (emission-absorption; the default), mip (maximum intensity\n"
    "                        projection through the TF's colours), iso (the surface where the field\n"
    "                        crosses --iso: the first crossing between lattice samples, bisected to\n"
    "                        1e-4 dt, opaque in the TF's colour at that value, lit as --shade says)\n"
    "                        or slice (the field through the TF's colours on the --plane planes:\n"
    "                        each ray shows the nearest one in front inside the data's box)\n"
    "  --iso V               iso: the iso value, in the data's units (as --range)\n"
    "  --plane px,py,pz,nx,ny,nz   slice: the plane through point p with normal n; repeat for up\n"
    "                        to 4 planes\n"
    "  --field N             iso, slice: the field of multi-field data they show (default 0)\n"
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
    "examples: each kind's section below, and the modes:\n"
    "  lanecast render engine.nhdr -o engine-mip.png --mode mip --tf gray\n"
    "  lanecast render engine.nhdr -o engine-iso.png --mode iso --iso 150 --shade phong\n"
    "  lanecast render engine.nhdr -o engine-slice.png --mode slice --plane 128,128,64,0,0,1 \\\n"
    "                  --plane 128,128,64,1,0,0 --tf gray\n"
    "  lanecast render 1tii.pdb -o 1tii-iso.png --mode iso --iso 0.5 --fields element --field 1 --shade\n"
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
    int iso_set, field_set; /* --iso, --field given */
} ropts;

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
    static const char *const flags[] = {"--tf",     "--tau",    "--range",   "--dt",   "--alpha-stop", "--method",
                                        "--packet", "--target", "--threads", "--tile", "--mode",       "--iso",
                                        "--plane",  "--field"};
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
        else if (!strcmp(v, "iso")) o->rd.mode = LC_MODE_ISO;
        else if (!strcmp(v, "slice")) o->rd.mode = LC_MODE_SLICE;
        else {
            fprintf(stderr, "%s: --mode: '%s' is not a render mode (dvr, mip, iso, slice)\n", o->cmd, v);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--iso")) return o->iso_set = 1, arg_float(o->cmd, a, v, -3e38f, 3e38f, &o->rd.iso) ? -1 : 1;
    if (!strcmp(a, "--field"))
        return o->field_set = 1, arg_int(o->cmd, a, v, 0, LC_MAX_FIELDS - 1, &o->rd.field) ? -1 : 1;
    if (!strcmp(a, "--plane")) {
        if (o->rd.nplanes == LC_MAX_PLANES) {
            fprintf(stderr, "%s: --plane: at most %d planes\n", o->cmd, LC_MAX_PLANES);
            return -1;
        }
        return arg_plane(o->cmd, a, v, &o->rd.planes[o->rd.nplanes++]) ? -1 : 1;
    }
    if (lc_target_from_name(v, &o->target) != LC_OK) { /* --target */
        fprintf(stderr, "%s: --target: %s\n", o->cmd, lc_last_error());
        return -1;
    }
    o->target_set = 1;
    return 1;
}

/* The mode's own flags: each is needed by its mode and refused by the
 * others (it would be ignored). */
static int check_mode(const ropts *o)
{
    lc_mode m = o->rd.mode;
    if (m == LC_MODE_ISO && !o->iso_set) {
        fprintf(stderr, "%s: --mode iso needs --iso VALUE\n", o->cmd);
        return -1;
    }
    if (m == LC_MODE_SLICE && o->rd.nplanes == 0) {
        fprintf(stderr, "%s: --mode slice needs at least one --plane px,py,pz,nx,ny,nz\n", o->cmd);
        return -1;
    }
    const char *stray = m != LC_MODE_ISO && o->iso_set ? "--iso"
                        : m != LC_MODE_SLICE && o->rd.nplanes ? "--plane"
                        : m != LC_MODE_ISO && m != LC_MODE_SLICE && o->field_set ? "--field"
                                                                                 : NULL;
    if (stray) {
        fprintf(stderr, "%s: %s applies to --mode %s only\n", o->cmd, stray,
                !strcmp(stray, "--iso") ? "iso" : !strcmp(stray, "--plane") ? "slice" : "iso or slice");
        return -1;
    }
    return 0;
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
        else if ((r = parse_view(o, argc, argv, &i, &camera_set)) || (r = parse_render(o, argc, argv, &i))) {
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
    if (check_mode(o)) return -1;
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
static const cli_kind *decide_kind(ropts *o, lc_device *dev, lc_kind forced, int *usage)
{
    lc_kind kind = forced;
    if (kind == LC_KIND_NONE) {
        lc_file_info fi;
        lc_load_desc ld = {.format = o->load.format};
        if (lc_file_probe(dev, o->input, &ld, &fi) != LC_OK) {
            fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
            return NULL;
        }
        kind = fi.kind;
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
static lc_status load(ropts *o, lc_device *dev, int demo, const cli_kind *kind, lc_volume **vol, lc_tf **tf)
{
    lc_status s;
    if (demo) {
        s = cli_demo_scene(dev, vol, o->tf ? NULL : tf);
    } else {
        lc_load_desc ld = {.format = o->load.format, .options = o->load.opt, .noptions = o->load.n};
        s = lc_volume_load(dev, o->input, &ld, vol);
    }
    if (s != LC_OK) return s;
    s = kind->apply(*vol, &o->rd);
    if (s != LC_OK || *tf) return s;
    if (o->tf && (strchr(o->tf, '.') || strchr(o->tf, '/'))) return lc_tf_load(dev, o->tf, tf);
    return kind->default_tf(dev, *vol, o->tf, o->tau, tf);
}

static int run(ropts *o, int demo)
{
    int rc = CLI_EXIT_FAIL, usage = 0;
    lc_device *dev = NULL;
    lc_volume *vol = NULL;
    lc_tf *tf = NULL;
    float *rgba = NULL;
    /* fail on an unwritable output before any long work */
    if (lc_image_check(NULL, o->output) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    lc_device_desc dd = {.target = o->target_set ? o->target : LC_TARGET_AUTO, .threads = o->threads};
    if (lc_device_create(&dd, &dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    const cli_kind *kind = decide_kind(o, dev, demo ? LC_KIND_PARTICLES : LC_KIND_NONE, &usage);
    if (!kind) {
        lc_device_destroy(dev);
        return usage ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
    }
    struct timespec ts0;
    clock_gettime(CLOCK_MONOTONIC, &ts0);
    lc_status s = load(o, dev, demo, kind, &vol, &tf);
    if (s != LC_OK) goto fail;
    double load_s = seconds_since(&ts0);
    o->rd.volume = vol;
    o->rd.tf = tf;
    if (demo && o->rd.shading == LC_SHADE_NONE) o->rd.shading = LC_SHADE_PHONG;
    if (o->progress) o->rd.progress = progress;
    rgba = malloc(sizeof(float) * 4 * (size_t)o->rd.width * (size_t)o->rd.height);
    if (!rgba) {
        fprintf(stderr, "%s: out of memory for a %dx%d image\n", o->cmd, o->rd.width, o->rd.height);
        goto out;
    }
    lc_render_stats st;
    s = lc_render(dev, &o->rd, rgba, &st);
    if (s != LC_OK) goto fail;
    lc_image_desc id = {o->rd.width, o->rd.height, rgba, o->background, o->alpha};
    s = lc_image_write(dev, o->output, &id);
    if (s != LC_OK) goto fail;
    if (!o->quiet) printf("wrote %s (%dx%d)\n", o->output, o->rd.width, o->rd.height);
    if (o->stats) print_stats(o, kind, vol, load_s, &st);
    rc = 0;
    goto out;
fail:
    fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
out:
    free(rgba);
    lc_tf_destroy(tf);
    lc_volume_destroy(vol);
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
