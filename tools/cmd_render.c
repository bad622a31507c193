/* lanecast render / lanecast demo: load (or generate) data, render, write.
 * Kind-neutral: the kinds' flags, defaults and stats come from their rows
 * (cli_kind.h); the kind is decided once, from the input file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <pthread.h>
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
    "  --max-memory SIZE     refuse inputs needing more memory than SIZE (e.g. 512M, 8G; default 3/4\n"
    "                        of the physical memory), e.g. --max-memory 2G\n"
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
    "camera (default: perspective, an oblique three-quarter view framing the data: azimuth 35,\n"
    "elevation 25 degrees, +y up):\n"
    "  --size WxH            image size in pixels (default 1024x1024)\n"
    "  --eye x,y,z --at x,y,z --up x,y,z   view (up defaults to 0,1,0)\n"
    "  --fov DEG             vertical field of view (default 40)\n"
    "  --ortho HEIGHT        orthographic projection with this image-plane height (0 = frame the data)\n"
    "  --view AZ,EL          frame the data from azimuth AZ degrees around +y (0 = from +z, 90 =\n"
    "                        from +x) and elevation EL degrees (default 35,25; 0,0 looks down -z)\n"
    "  --orbit N             N images around the data, the azimuth stepping 360/N degrees from the\n"
    "                        view (or, with --eye/--at, rotating the eye about --at around --up);\n"
    "                        -o names each with a printf-style number, e.g. -o orbit_%03d.png\n"
    "  examples: lanecast render engine.nhdr -o engine.png --view 0,0 --fov 30\n"
    "            lanecast render 1tii.pdb --orbit 36 -o spin_%02d.png --size 512x512\n"
    "\n"
    "classification and sampling:\n"
    "  --tf FILE|PRESET      transfer function: a SPEC.md JSON file, a ParaView colour-map preset\n"
    "                        (.json, an array of {\"Name\", \"RGBPoints\", \"Points\"}: its x range\n"
    "                        becomes the value range in use, alpha becomes tau = -ln(1 - alpha) per\n"
    "                        world unit; without \"Points\" the kind's default opacity), or a preset\n"
    "                        name (its own ramp from v = 0.1 to --tau at v = 1): heat, cool, gray,\n"
    "                        demo, viridis, inferno, magma, plasma, cool-warm, grayscale\n"
    "  --colormap NAME       colours of a preset above on the kind's default opacity (for volumes,\n"
    "                        the histogram rule; see the volumes section)\n"
    "  --opacity V:TAU,...   opacity points, V the normalised value in [0, 1] (increasing), TAU the\n"
    "                        extinction per world unit; V spans --range, the TF file's, else the\n"
    "                        data's min..max\n"
    "  --tau T               peak extinction per world unit of a preset or default (default: by kind)\n"
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
    "  --alpha               write an alpha channel instead of compositing the background (PNG:\n"
    "                        straight RGBA; EXR: premultiplied)\n"
    "  examples: lanecast render headsq.nhdr -o head.png --colormap cool-warm --shade\n"
    "            lanecast render engine.nhdr -o e.png --colormap inferno --opacity 0:0,0.4:0,1:0.2\n"
    "            lanecast render neghip.nhdr -o n.exr --tf 'Blue Orange.json' --alpha\n"
    "\n"
    "execution:\n"
    "  --method M            how the kind walks its data (each kind's section below lists its methods)\n"
    "  --packet N            rays per packet side: 8 = 8x8 groups (default), 1 = lane-width packets\n"
    "  --target T            scalar, sse4, avx2, avx512, avx512_8 or auto (default auto; see lanecast\n"
    "                        targets); avx512_8 = AVX-512 instructions at 8 lanes, for width studies\n"
    "  --threads N           worker threads (default: all CPUs)\n"
    "  --tile N              tile side in pixels (default 32)\n"
    "  --stats               print load, build and render times and counters\n"
    "  --progress            progress on stderr, one line updated in place, for reading (a bar:\n"
    "                        the part of the file read), BVH builds (elapsed time) and renders\n"
    "                        (a bar) that take over a second\n"
    "                        (default when stderr is a terminal)\n"
    "  --quiet               print nothing but errors (and no progress)\n"
    "  example: lanecast render embryo.nhdr -o embryo.png --size 2048x2048 --stats --threads 8\n"
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
    const char *tf, *colormap;
    float tau;
    float opacity[2 * 256]; /* --opacity points [v, tau] */
    int nopacity;
    float view[2];          /* --view azimuth, elevation */
    int orbit;              /* --orbit N, 0 = off */
    int camera_set, view_set;
    lc_vec3 background;
    int alpha, stats, quiet, progress;
    /* trajectories: --frame, or --frames first:end:step (end -1 = to the last) */
    int64_t frame, first, end, step;
    int seq;
    const char *topology;
    int iso_set, field_set; /* --iso, --field given */
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
    static const char *const flags[] = {"--size", "--eye",        "--at",   "--up",   "--fov",
                                        "--ortho", "--background", "--view", "--orbit"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    lc_camera *c = &o->rd.camera;
    if (!strcmp(a, "--size")) return arg_size(o->cmd, a, v, &o->rd.width, &o->rd.height) ? -1 : 1;
    if (!strcmp(a, "--eye")) return *camera_set |= 1, arg_vec3(o->cmd, a, v, &c->eye) ? -1 : 1;
    if (!strcmp(a, "--at")) return *camera_set |= 2, arg_vec3(o->cmd, a, v, &c->at) ? -1 : 1;
    if (!strcmp(a, "--up")) return arg_vec3(o->cmd, a, v, &c->up) ? -1 : 1;
    if (!strcmp(a, "--fov")) return arg_float_below(o->cmd, a, v, 0.01f, 179.0f, &c->fovy) ? -1 : 1; /* as lc_camera */
    if (!strcmp(a, "--background")) return arg_vec3(o->cmd, a, v, &o->background) ? -1 : 1;
    if (!strcmp(a, "--orbit")) return arg_int(o->cmd, a, v, 1, 100000, &o->orbit) ? -1 : 1;
    if (!strcmp(a, "--view")) {
        o->view_set = 1;
        if (arg_pair(o->cmd, a, v, o->view)) return -1;
        if (!(o->view[1] > -90.0f && o->view[1] < 90.0f) || !(fabsf(o->view[0]) <= 1e6f)) {
            fprintf(stderr, "%s: --view: '%s': expected AZ,EL in degrees with -90 < EL < 90\n", o->cmd, v);
            return -1;
        }
        return 1;
    }
    c->projection = LC_ORTHOGRAPHIC; /* --ortho */
    return arg_float(o->cmd, a, v, 0.0f, 1e30f, &c->height) ? -1 : 1;
}

/* --opacity v:tau,v:tau,...: v in [0, 1] increasing, tau >= 0. */
static int parse_opacity(ropts *o, const char *v)
{
    const char *p = v;
    o->nopacity = 0;
    for (int k = 0;; k++) {
        char *end;
        double x = strtod(p, &end), t = 0.0;
        const char *why = NULL;
        if (end == p || *end != ':') why = "expected V:TAU";
        else {
            const char *q = end + 1;
            t = strtod(q, &end);
            if (end == q) why = "expected V:TAU";
        }
        if (!why && (*end != ',' && *end)) why = "expected ',' or the end after V:TAU";
        if (!why && !(x >= 0.0 && x <= 1.0)) why = "V must lie in [0, 1]";
        if (!why && !(t >= 0.0 && isfinite(t))) why = "TAU must be a finite value >= 0";
        if (!why && k > 0 && x < o->opacity[2 * (k - 1)]) why = "V must not decrease";
        if (!why && k >= 256) why = "at most 256 points";
        if (why) {
            fprintf(stderr, "%s: --opacity: point %d (at character %d of '%s'): %s\n", o->cmd, k + 1, (int)(p - v) + 1, v,
                    why);
            return -1;
        }
        o->opacity[2 * k] = (float)x, o->opacity[2 * k + 1] = (float)t;
        o->nopacity = k + 1;
        if (!*end) return 0;
        p = end + 1;
    }
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
                                        "--packet", "--target", "--threads", "--tile", "--mode",       "--colormap",
                                        "--opacity", "--iso",   "--plane",   "--field"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--tf")) return o->tf = v, 1;
    if (!strcmp(a, "--colormap")) {
        for (int k = 0; lc_tf_preset_name(k); k++)
            if (!strcmp(v, lc_tf_preset_name(k))) return o->colormap = v, 1;
        char names[256] = "";
        for (int k = 0; lc_tf_preset_name(k); k++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? ", " : "", lc_tf_preset_name(k));
        fprintf(stderr, "%s: --colormap: '%s' is not a colour map (%s)\n", o->cmd, v, names);
        return -1;
    }
    if (!strcmp(a, "--opacity")) return parse_opacity(o, v) ? -1 : 1;
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

/* The input flags --frame, --frames, --topology and --dataset: 1 consumed, 0 not one, -1 bad. */
static int parse_input(ropts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (strcmp(a, "--frame") && strcmp(a, "--frames") && strcmp(a, "--topology") && strcmp(a, "--dataset") &&
        strcmp(a, "--max-memory"))
        return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--max-memory")) /* the loaders' memory limit (lc_load_desc option max_memory) */
        return arg_memory(o->cmd, a, v) || cli_load_add(&o->load, o->cmd, "max_memory", v) ? -1 : 1;
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
    o->view[0] = LC_CAMERA_AZIMUTH, o->view[1] = LC_CAMERA_ELEVATION;
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
    if (check_mode(o)) return -1;
    if (camera_set && camera_set != 3) {
        fprintf(stderr, "%s: give both --eye and --at (or neither, to frame the data)\n", o->cmd);
        return -1;
    }
    o->camera_set = camera_set;
    if (want_input && !o->input) {
        fprintf(stderr, "%s: no input file (see %s --help)\n", o->cmd, o->cmd);
        return -1;
    }
    if (o->view_set && camera_set) {
        fprintf(stderr, "%s: --view: give --view or --eye/--at, not both\n", o->cmd);
        return -1;
    }
    if (o->colormap && o->tf) {
        fprintf(stderr, "%s: --colormap: give --colormap or --tf, not both (a TF file or preset has its own colours)\n",
                o->cmd);
        return -1;
    }
    if (o->orbit && (o->seq || o->frame)) {
        fprintf(stderr, "%s: --orbit: give --orbit or --frame/--frames, not both\n", o->cmd);
        return -1;
    }
    if (!o->output || !o->output[0]) {
        fprintf(stderr, "%s: no output image: give -o OUT.png\n", o->cmd);
        return -1;
    }
    if (o->seq && o->frame) {
        fprintf(stderr, "%s: give --frame or --frames, not both\n", o->cmd);
        return -1;
    }
    if ((o->seq || o->orbit) && !sequence_name_ok(o->output)) {
        fprintf(stderr, "%s: %s needs an output name with one frame number in it, e.g. -o out_%%04d.png "
                "(got '%s')\n", o->cmd, o->orbit ? "--orbit" : "--frames", o->output);
        return -1;
    }
    if (o->seq && o->end >= 0 && (o->end - o->first + o->step - 1) / o->step > 1000000) {
        fprintf(stderr, "%s: --frames: more than a million images\n", o->cmd);
        return -1;
    }
    if (o->quiet) o->progress = 0;
    return 0;
}

/* ---- progress: one line on stderr, updated in place, shown only for work
 * that has taken over a second (o->progress: a terminal and not --quiet) */

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct progress_state {
    const char *label; /* "rendering", "frame 3/36", ... */
    double t0;
    int shown;
} progress_state;

static void progress_clear(progress_state *p)
{
    if (p->shown) fputs("\r\033[K", stderr), fflush(stderr);
    p->shown = 0;
}

static void render_progress(void *user, float f)
{
    progress_state *p = user;
    if (now_seconds() - p->t0 < 1.0 && !p->shown) return;
    if (f >= 1.0f) {
        progress_clear(p);
        return;
    }
    char bar[31];
    int n = (int)(30.0f * f);
    for (int i = 0; i < 30; i++) bar[i] = i < n ? '#' : '.';
    bar[30] = '\0';
    fprintf(stderr, "\r%s [%s] %3d%%", p->label, bar, (int)(100.0f * f));
    fflush(stderr);
    p->shown = 1;
}

/* Loading reports the fraction of the file read (lc_load_desc.progress);
 * building the volume (its BVH) none. A thread shows, after the first
 * second, a bar while reading and the elapsed time while building. */
typedef struct load_ticker {
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int done, started;
    const char *what;
    double t0;
    float fraction; /* of the file read; -1 = none reported yet */
} load_ticker;

static void load_progress(void *user, float f)
{
    load_ticker *t = user;
    if (!t->started) return;
    pthread_mutex_lock(&t->mu);
    t->fraction = f;
    pthread_mutex_unlock(&t->mu);
}

static void *ticker_main(void *arg)
{
    load_ticker *t = arg;
    static const char spin[] = "|/-\\";
    int shown = 0, k = 0;
    pthread_mutex_lock(&t->mu);
    while (!t->done) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 200000000L;
        if (until.tv_nsec >= 1000000000L) until.tv_sec++, until.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&t->cv, &t->mu, &until);
        double el = now_seconds() - t->t0;
        if (!t->done && el >= 1.0 && t->fraction >= 0.0f && t->fraction < 1.0f) {
            char bar[31];
            int n = (int)(30.0f * t->fraction);
            for (int i = 0; i < 30; i++) bar[i] = i < n ? '#' : '.';
            bar[30] = '\0';
            fprintf(stderr, "\r\033[Kreading %s [%s] %3d%%", t->what, bar, (int)(100.0f * t->fraction));
            fflush(stderr);
            shown = 1;
        } else if (!t->done && el >= 1.0) {
            fprintf(stderr, "\r\033[K%c %s %s  %.1f s", spin[k++ & 3], t->fraction >= 1.0f ? "building" : "loading and building",
                    t->what, el);
            fflush(stderr);
            shown = 1;
        }
    }
    if (shown) fputs("\r\033[K", stderr), fflush(stderr);
    pthread_mutex_unlock(&t->mu);
    return NULL;
}

static void ticker_start(load_ticker *t, const char *what, int on)
{
    memset(t, 0, sizeof *t);
    if (!on) return;
    t->what = what;
    t->t0 = now_seconds();
    t->fraction = -1.0f;
    pthread_mutex_init(&t->mu, NULL);
    pthread_cond_init(&t->cv, NULL);
    t->started = pthread_create(&t->thread, NULL, ticker_main, t) == 0;
}

static void ticker_stop(load_ticker *t)
{
    if (!t->started) return;
    pthread_mutex_lock(&t->mu);
    t->done = 1;
    pthread_cond_signal(&t->cv);
    pthread_mutex_unlock(&t->mu);
    pthread_join(t->thread, NULL);
    pthread_mutex_destroy(&t->mu);
    pthread_cond_destroy(&t->cv);
}

/* The kind of the input, decided once through the formats registry; flags of
 * another kind are an error (they would be ignored). Returns the row or NULL
 * (message printed; *usage set when the flags were at fault). *fopts: the
 * option keys of the file's format ("" for the demo). */
static const cli_kind *decide_kind(ropts *o, lc_device *dev, lc_kind forced, int *usage, int64_t *frames,
                                   const char **fopts)
{
    lc_kind kind = forced;
    *frames = 1;
    *fopts = "";
    if (kind == LC_KIND_NONE && o->load.format && o->input) {
        /* --dims / --raw-particles name a headerless format: a file that says
           what it is (magic bytes) has its own header, and the flag would be
           read over it */
        lc_file_info fi;
        if (lc_file_probe(dev, o->input, NULL, &fi) == LC_OK && strcmp(fi.format, o->load.format) &&
            strncmp(fi.format, "raw", 3)) {
            int dims = !strcmp(o->load.format, "raw-volume");
            fprintf(stderr, "%s: %s does not apply to %s: it is a %s file, whose header gives %s (drop %s)\n", o->cmd,
                    dims ? "--dims" : "--raw-particles", o->input, fi.format, dims ? "the sizes" : "the particles",
                    dims ? "--dims" : "--raw-particles");
            *usage = 1;
            return NULL;
        }
    }
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
        lc_format_info f;
        for (int i = 0; i < lc_format_count(); i++)
            if (lc_format_get(i, &f) == LC_OK && !strcmp(f.name, fi.format)) *fopts = f.options;
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
/* The TF from its parts: colours from the TF file, else the kind's default
 * (--tf PRESET or --colormap); opacity from --opacity, else the file (unless
 * a ParaView colour preset gave none), else the default; the range goes with
 * the opacity's source (--opacity: the file's, else the data's). */
static lc_status make_tf(ropts *o, lc_device *dev, const cli_kind *kind, lc_volume *vol, lc_tf **tf)
{
    /* a preset name is a preset; otherwise a name with '.' or '/', or any
       existing path (a directory too: lc_tf_load then says what it is), is a
       file, and anything else an unknown preset */
    int preset = 0;
    for (int i = 0; o->tf && lc_tf_preset_name(i); i++) preset |= !strcmp(o->tf, lc_tf_preset_name(i));
    int is_file = o->tf && !preset && (strchr(o->tf, '.') || strchr(o->tf, '/') || access(o->tf, F_OK) == 0);
    lc_tf *file = NULL, *def = NULL;
    lc_status s = LC_OK;
    if (is_file) s = lc_tf_load(dev, o->tf, &file);
    if (s != LC_OK) return s;
    int file_opacity = file && !lc_tf_default_opacity(file, 0);
    if (file && (file_opacity || o->nopacity) && !o->nopacity) return *tf = file, LC_OK; /* as it always was */
    if (!file || !file_opacity) {
        cli_tf_req req = {is_file ? NULL : o->tf, o->colormap, o->tau};
        s = kind->default_tf(dev, vol, &req, &def);
        if (s != LC_OK || (!file && !o->nopacity)) {
            lc_tf_destroy(file);
            return *tf = def, s;
        }
    }
    const lc_tf *colours = file ? file : def;
    int n = lc_tf_field_count(colours);
    if (def && lc_tf_field_count(def) > n) n = lc_tf_field_count(def);
    lc_tf_field f[LC_MAX_FIELDS];
    for (int i = 0; i < n && s == LC_OK; i++) {
        lc_tf_field c, p;
        s = lc_tf_get_field(colours, i % lc_tf_field_count(colours), &c);
        if (s == LC_OK && !o->nopacity) s = lc_tf_get_field(def, i % lc_tf_field_count(def), &p);
        if (s != LC_OK) break;
        f[i] = c;
        if (o->nopacity) {
            f[i].opacity = o->opacity, f[i].nopacity = o->nopacity;
            f[i].has_range = file ? c.has_range : 0;
        } else {
            f[i].opacity = p.opacity, f[i].nopacity = p.nopacity;
            f[i].has_range = p.has_range, f[i].range[0] = p.range[0], f[i].range[1] = p.range[1];
        }
    }
    if (s == LC_OK) s = lc_tf_create(dev, f, n, tf);
    lc_tf_destroy(file);
    lc_tf_destroy(def);
    return s;
}

/* Loads (or makes) the volume and its TF. */
static lc_status load(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t frame, lc_volume **vol,
                      lc_tf **tf)
{
    lc_status s;
    if (demo) {
        s = cli_demo_scene(dev, vol, o->tf || o->colormap || o->nopacity ? NULL : tf);
    } else {
        load_ticker tk;
        ticker_start(&tk, o->input, o->progress);
        lc_load_desc ld = {.format = o->load.format, .companion = o->topology, .frame = frame,
                           .options = o->load.opt, .noptions = o->load.n,
                           .progress = tk.started ? load_progress : NULL, .progress_user = &tk};
        s = lc_volume_load(dev, o->input, &ld, vol);
        ticker_stop(&tk);
    }
    if (s != LC_OK) return s;
    s = kind->apply(*vol, &o->rd);
    if (s != LC_OK || *tf) return s;
    return make_tf(o, dev, kind, *vol, tf);
}

/* Warnings (a missing topology, ...) on stderr; errors are printed by the caller. */
static void log_warning(void *user, lc_log_level level, const char *msg)
{
    static char last[1024]; /* once per sequence, not once per frame */
    if (level != LC_LOG_WARNING || !strncmp(last, msg, sizeof last - 1)) return;
    snprintf(last, sizeof last, "%s", msg);
    fprintf(stderr, "%s: warning: %s\n", (const char *)user, msg);
}

/* Rotates v about the axis through the origin (unit) by a radians. */
static lc_vec3 rotate(lc_vec3 v, lc_vec3 k, float a)
{
    float c = cosf(a), s = sinf(a), d = (k.x * v.x + k.y * v.y + k.z * v.z) * (1.0f - c);
    lc_vec3 x = {k.y * v.z - k.z * v.y, k.z * v.x - k.x * v.z, k.x * v.y - k.y * v.x};
    return (lc_vec3){v.x * c + x.x * s + k.x * d, v.y * c + x.y * s + k.y * d, v.z * c + x.z * s + k.z * d};
}

/* The camera of orbit image i (of o->orbit; i = 0 without --orbit). */
static lc_status view_camera(const ropts *o, const lc_volume *vol, int i, lc_camera *cam)
{
    *cam = o->rd.camera;
    float step = o->orbit ? 360.0f * (float)i / (float)o->orbit : 0.0f;
    if (!o->camera_set) {
        lc_volume_info vi;
        lc_status s = lc_volume_get_info(vol, &vi);
        return s != LC_OK ? s : lc_camera_frame(&vi.bounds, o->view[0] + step, o->view[1], cam);
    }
    if (step == 0.0f) return LC_OK; /* an explicit camera exactly as given */
    lc_vec3 up = cam->up;
    float n = sqrtf(up.x * up.x + up.y * up.y + up.z * up.z);
    up = n > 0.0f ? (lc_vec3){up.x / n, up.y / n, up.z / n} : (lc_vec3){0.0f, 1.0f, 0.0f};
    lc_vec3 d = {cam->eye.x - cam->at.x, cam->eye.y - cam->at.y, cam->eye.z - cam->at.z};
    d = rotate(d, up, step * 3.14159265f / 180.0f);
    cam->eye = (lc_vec3){cam->at.x + d.x, cam->at.y + d.y, cam->at.z + d.z};
    return LC_OK;
}

/* Loads frame f, renders it (or its orbit) and writes the image(s). */
static lc_status render_one(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t f, const char *out,
                            lc_tf **tf, float *rgba, int index, int count)
{
    lc_volume *vol = NULL;
    struct timespec ts0;
    clock_gettime(CLOCK_MONOTONIC, &ts0);
    lc_status s = load(o, dev, demo, kind, f, &vol, tf);
    double load_s = seconds_since(&ts0);
    lc_camera given = o->rd.camera;
    int views = o->orbit ? o->orbit : 1;
    char name[4096];
    for (int v = 0; s == LC_OK && v < views; v++) {
        if (o->orbit) frame_name(o->output, v, name, sizeof name);
        else snprintf(name, sizeof name, "%s", out);
        s = view_camera(o, vol, v, &o->rd.camera);
        char label[64];
        if (count > 1 || views > 1)
            snprintf(label, sizeof label, "rendering %d/%d", (o->orbit ? v : index) + 1, o->orbit ? views : count);
        else
            snprintf(label, sizeof label, "rendering");
        progress_state ps = {label, now_seconds(), 0};
        o->rd.progress = o->progress ? render_progress : NULL;
        o->rd.progress_user = &ps;
        o->rd.volume = vol;
        o->rd.tf = *tf;
        lc_render_stats st;
        if (s == LC_OK) s = lc_render(dev, &o->rd, rgba, &st);
        progress_clear(&ps);
        o->rd.camera = given;
        lc_image_desc id = {o->rd.width, o->rd.height, rgba, o->background, o->alpha};
        if (s == LC_OK) s = lc_image_write(dev, name, &id);
        if (s == LC_OK && !o->quiet) printf("wrote %s (%dx%d)\n", name, o->rd.width, o->rd.height);
        if (s == LC_OK && o->stats) print_stats(o, kind, vol, load_s, &st);
        if (s != LC_OK && o->orbit)
            fprintf(stderr, "%s: orbit image %d (%s): %s; the orbit stops here\n", o->cmd, v, name, lc_last_error());
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
    if (o->orbit) frame_name(o->output, 0, out, sizeof out);
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
    const char *fopts = "";
    const cli_kind *kind = decide_kind(o, dev, demo ? LC_KIND_PARTICLES : LC_KIND_NONE, &usage, &frames, &fopts);
    if (kind && !demo && kind->defaults &&
        kind->defaults(o->cmd, &o->load, fopts, o->tf || o->colormap || o->nopacity))
        kind = NULL;
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
    rgba = malloc(sizeof(float) * 4 * (size_t)o->rd.width * (size_t)o->rd.height);
    if (!rgba) {
        fprintf(stderr, "%s: out of memory for a %dx%d image\n", o->cmd, o->rd.width, o->rd.height);
        goto out;
    }
    int count = (int)((end - first + step - 1) / step), index = 0;
    for (int64_t f = first; f < end; f += step, index++) {
        if (o->seq) frame_name(o->output, f, out, sizeof out);
        if (render_one(o, dev, demo, kind, f, out, &tf, rgba, index, count) != LC_OK) {
            if (o->seq)
                fprintf(stderr, "%s: frame %lld (%s): %s; the sequence stops here\n", o->cmd, (long long)f, out,
                        lc_last_error());
            else if (!o->orbit)
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
