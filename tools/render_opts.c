/* lanecast render / demo: help, options and their checks (render_opts.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "render_opts.h"

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
    "  --resample N          particles: deposit their field at the nodes of an N^3 grid over their\n"
    "                        bounds (as lanecast resample does) and render that grid with the grid\n"
    "                        renderer, the same camera, TF, range and mode: frame rate over\n"
    "                        exactness (docs/BENCHMARKS.md gives the error); several fields are\n"
    "                        summed and drawn with field 0's TF; --stats gives the deposit's time\n"
    "                        and memory; --max-memory bounds the grid too\n"
    "  --frames A:B[:S]      render frames A, A+S, ... before B (B omitted: to the end; S default 1)\n"
    "                        as an image sequence; -o then names each image with a printf-style\n"
    "                        frame number, e.g. -o out_%04d.png; the first error stops the sequence\n"
    "  --topology FILE       a companion file: the topology of a trajectory, a PSF for DCD (default:\n"
    "                        the DCD's name with .psf), a .gro, .pdb or .psf for XTC and TRR\n"
    "                        (default: the trajectory's name with .gro, .pdb or .psf, the first found)\n"
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
    "                        each ray shows the nearest one in front inside the data's box);\n"
    "                        project: column maps of particles (section \"projections\" below)\n"
    "  --iso V               iso: the iso value, in the data's units (as --range)\n"
    "  --plane px,py,pz,nx,ny,nz   slice: the plane through point p with normal n; repeat for up\n"
    "                        to 4 planes\n"
    "  --field N             iso, slice: the field of multi-field data they show (default 0)\n"
    "  --shade [MODE]        none, diffuse (the default when MODE is omitted) or phong\n"
    "  --lighting KA,KD,KS[,P]  the headlight's ambient, diffuse and specular weights (>= 0) and\n"
    "                        the integer Phong exponent P in 1..256: diffuse gives rgb (KA + KD |n.l|),\n"
    "                        phong adds KS |n.h|^P (default 0.2,0.8,0.4,16; P 16 when omitted)\n"
    "  --alpha-stop A        early ray termination opacity in (0, 1] (default 0.97; 1 = never)\n"
    "  --background r,g,b    background colour (default 0,0,0)\n"
    "  --alpha               write an alpha channel instead of compositing the background (PNG:\n"
    "                        straight RGBA; EXR: premultiplied)\n"
    "  examples: lanecast render headsq.nhdr -o head.png --colormap cool-warm --shade\n"
    "            lanecast render engine.nhdr -o e.png --colormap inferno --opacity 0:0,0.4:0,1:0.2\n"
    "            lanecast render engine.nhdr -o shiny.png --shade phong --lighting 0.1,0.7,0.8,64\n"
    "            lanecast render neghip.nhdr -o n.exr --tf 'Blue Orange.json' --alpha\n"
    "\n"
    "execution:\n"
    "  --method M            how the kind walks its data (each kind's section below lists its methods)\n"
    "  --packet N            rays per packet side: 8 = 8x8 groups (default), 1 = lane-width packets\n"
    "  --target T            scalar, sse4, avx2, avx512, avx512_8 or auto (default auto; see lanecast\n"
    "                        targets); avx512_8 = AVX-512 instructions at 8 lanes, for width studies\n"
    "  --threads N           worker threads (default: all CPUs)\n"
    "  --tile N              tile side in pixels (default 32)\n"
    "  --stats               print load, build and render times and counters (under mpirun: per rank)\n"
    "  --composite C         under mpirun, how dvr regions become one image: chain (the default) hands\n"
    "                        the image from rank to rank in visibility order and each rank's rays go\n"
    "                        on from what the ranks in front left: one process's image to the bit;\n"
    "                        swap blends each region alone, then binary swap (fewer bytes a rank,\n"
    "                        no fill time; round-off of the \"over\", ~1e-5). mip, iso, slice: swap\n"
    "  --bands N             the chain's bands of rows (default max(16, 4 x ranks))\n"
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


const cli_kind *const cli_kinds[NKINDS] = {&cli_particles, &cli_grid, &cli_rbf};

const cli_kind *cli_kind_of(lc_kind kind)
{
    for (int k = 0; k < NKINDS; k++)
        if (cli_kinds[k]->kind == kind) return cli_kinds[k];
    return NULL;
}

int cli_files_append(char **files, const char *first, const char *path)
{
    size_t had = *files ? strlen(*files) : 0, add = (had ? 0 : strlen(first) + 1) + strlen(path) + 2;
    char *f = realloc(*files, had + add);
    if (!f) return -1;
    if (!had) snprintf(f, add, "%s\n", first), had = strlen(f);
    snprintf(f + had, add, "%s\n", path);
    *files = f;
    return 0;
}

int cli_load_file(cli_load *l, const char *cmd, char **files, const char *first, const char *path)
{
    if (cli_files_append(files, first, path)) {
        fprintf(stderr, "%s: out of memory for the list of inputs\n", cmd);
        return -1;
    }
    for (int i = 0; i < l->n; i++)
        if (!strcmp(l->opt[i].key, "files")) return l->opt[i].value = *files, 0;
    if (l->n == CLI_MAX_OPTIONS) {
        fprintf(stderr, "%s: too many load options (at the list of inputs)\n", cmd);
        return -1;
    }
    l->opt[l->n].key = "files";
    l->opt[l->n++].value = *files;
    return 0;
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
                                        "--opacity", "--iso",   "--plane",   "--field", "--lighting", "--composite",
                                        "--bands"};
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
    if (!strcmp(a, "--lighting")) return arg_lighting(o->cmd, a, v, &o->rd.lighting) ? -1 : 1;
    if (!strcmp(a, "--dt")) return arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->rd.dt) ? -1 : 1;
    if (!strcmp(a, "--alpha-stop")) return arg_float(o->cmd, a, v, 1e-6f, 1.0f, &o->rd.alpha_stop) ? -1 : 1;
    if (!strcmp(a, "--method")) return parse_method(o, v) ? -1 : 1;
    if (!strcmp(a, "--packet")) return arg_int(o->cmd, a, v, 1, 64, &o->rd.packet) ? -1 : 1;
    if (!strcmp(a, "--threads")) return arg_int(o->cmd, a, v, 1, 1024, &o->threads) ? -1 : 1;
    if (!strcmp(a, "--tile")) return arg_int(o->cmd, a, v, 1, 4096, &o->rd.tile) ? -1 : 1;
    if (!strcmp(a, "--bands")) return arg_int(o->cmd, a, v, 1, 1 << 20, &o->bands) ? -1 : 1;
    if (!strcmp(a, "--composite")) {
        static const char *const ways[] = {"auto", "chain", "swap"};
        for (int k = 0; k < 3; k++)
            if (!strcmp(v, ways[k])) return o->composite = k, 1;
        fprintf(stderr, "%s: --composite: '%s' is not chain, swap or auto\n", o->cmd, v);
        return -1;
    }
    if (!strcmp(a, "--mode")) {
        if (!strcmp(v, "dvr")) o->rd.mode = LC_MODE_DVR;
        else if (!strcmp(v, "mip")) o->rd.mode = LC_MODE_MIP;
        else if (!strcmp(v, "iso")) o->rd.mode = LC_MODE_ISO;
        else if (!strcmp(v, "slice")) o->rd.mode = LC_MODE_SLICE;
        else if (!strcmp(v, "project")) o->pj.on = 1; /* not a ray-casting mode: cli_project.c */
        else {
            fprintf(stderr, "%s: --mode: '%s' is not a render mode (dvr, mip, iso, slice, project)\n", o->cmd, v);
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
        strcmp(a, "--max-memory") && strcmp(a, "--resample"))
        return 0;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--max-memory")) /* the loaders' memory limit (lc_load_desc option max_memory), and --resample's */
        return arg_memory_bytes(o->cmd, a, v, &o->max_memory) || cli_load_add(&o->load, o->cmd, "max_memory", v) ? -1 : 1;
    if (!strcmp(a, "--resample")) return arg_int(o->cmd, a, v, 2, 4096, &o->resample) ? -1 : 1;
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

void render_frame_name(const char *pattern, int64_t f, char *out, size_t n)
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
    for (int k = 0; k < NKINDS; k++) fputs(cli_kinds[k]->help, stdout);
    fputs(cli_project_help, stdout);
}

int render_parse(ropts *o, int argc, char **argv, int want_input)
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
                 (want_input && (r = cli_project_flag(o, argc, argv, &i))) ||
                 (want_input && (r = parse_input(o, argc, argv, &i)))) {
            if (r < 0) return -1;
        } else {
            r = cli_input_flag(o->cmd, argc, argv, &i, &o->load, o->first_flag);
            if (r < 0) return -1;
            if (r) continue;
            if (a[0] == '-' && a[1]) {
                fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", o->cmd, a, o->cmd);
                return -1;
            } else if (want_input && !o->input) {
                o->input = a;
            } else if (want_input) { /* the files of a DICOM series */
                if (cli_load_file(&o->load, o->cmd, &o->files, o->input, a)) return -1;
            } else {
                fprintf(stderr, "%s: unexpected argument '%s'\n", o->cmd, a);
                return -1;
            }
        }
    }
    if (check_mode(o) || cli_project_check(o)) return -1;
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
    if (o->resample && o->pj.on) {
        fprintf(stderr, "%s: --resample: give --resample or --mode project, not both (a projection is exact already)\n",
                o->cmd);
        return -1;
    }
    if (o->quiet) o->progress = 0;
    return 0;
}
