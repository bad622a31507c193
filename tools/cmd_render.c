/* lanecast render / lanecast demo: load (or generate) data, render, write. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "cmd_render_grid.h"

static const char render_help[] =
    "usage: lanecast render INPUT -o OUT.png|.exr|.tif [options]\n"
    "       lanecast demo [-o OUT.png] [options]\n"
    "\n"
    "Volume ray casting of particle data (sums of truncated Gaussians, Knoll et al. 2014) and of\n"
    "structured volumes (implicit min-max BVH, Knoll et al. 2011); the kind follows INPUT.\n"
    "The image format follows the extension of OUT (any OpenImageIO writes; 8-bit for png/jpg,\n"
    "float for exr/tif). The file is written under a temporary name and renamed when complete.\n"
    "\n"
    "input:\n"
    "  INPUT                 .xyz (element x y z), .pdb/.ent (ATOM/HETATM), optionally .gz;\n"
    "                        raw float32 x,y,z triples with --raw-particles\n"
    "  --raw-particles N     INPUT holds exactly N little-endian float32 xyz triples (needs --radius)\n"
    "  --radius R            radius of every particle (default: covalent radius by element)\n"
    "  --radius-scale S      multiply element radii by S\n"
    "  --fields MODE         none (one field) or element (one field per element, up to 8)\n"
    "  --drop-invalid        drop particles with bad data (counted) instead of failing\n"
    "  --leaf N              particles per BVH leaf, 1..32 (default 4)\n"
    "\n"
    "camera (default: perspective, looking down -z at the data, framing it):\n"
    "  --size WxH            image size in pixels (default 1024x1024)\n"
    "  --eye x,y,z --at x,y,z --up x,y,z   view (up defaults to 0,1,0)\n"
    "  --fov DEG             vertical field of view (default 40)\n"
    "  --ortho HEIGHT        orthographic projection with this image-plane height (0 = frame the data)\n"
    "\n"
    "classification and sampling:\n"
    "  --tf FILE|PRESET      transfer function: SPEC.md JSON file, or heat, cool, gray, demo\n"
    "  --tau T               peak extinction per world unit of a preset (default 1 / largest radius)\n"
    "  --range LO,HI         value range mapped to [0, 1] (default: the TF's, else 0,kappa)\n"
    "  --dt DT               sampling step in world units (default: a quarter of the smallest radius)\n"
    "  --sigma S             truncation radius in radii (default 2)\n"
    "  --kappa K             global density scale (default 1)\n"
    "  --shade [MODE]        none, diffuse (the default when MODE is omitted) or phong\n"
    "  --alpha-stop A        early ray termination opacity in (0, 1] (default 0.97; 1 = never)\n"
    "  --background r,g,b    background colour (default 0,0,0)\n"
    "  --alpha               write an alpha channel instead of compositing the background\n"
    "  --spheres SCALE       also ray-trace opaque spheres of radius SCALE * r (paper §5.2)\n"
    "\n"
    "execution:\n"
    "  --method M            coherent (default; buffered packets) or direct (per-sample gather)\n"
    "  --packet N            rays per packet side: 8 = 8x8 groups (default), 1 = lane-width packets\n"
    "  --buffer K            coherent buffer samples per ray (default 32, 64/M for M fields)\n"
    "  --target T            scalar, sse4, avx2, avx512, avx512_8 or auto (default auto; see lanecast\n"
    "                        targets); avx512_8 = AVX-512 instructions at 8 lanes, for width studies\n"
    "  --threads N           worker threads (default: all CPUs)\n"
    "  --tile N              tile side in pixels (default 32)\n"
    "  --stats               print load, build and render times and counters\n"
    "  --progress            show a progress line on stderr (default when stderr is a terminal)\n"
    "  --quiet               print nothing but errors\n"
    "\n"
    "examples:\n"
    "  lanecast render 1tii.pdb -o 1tii.png --shade --fields element --tf demo\n"
    "  lanecast render atoms.f32 --raw-particles 1000000 --radius 0.5 -o big.exr --stats\n"
    "\n"
    "exit status: 0 ok, 1 bad input or failed work (one message on stderr), 2 bad usage\n";

typedef struct ropts {
    const char *cmd;
    const char *input, *output;
    lc_particles_load_options load;
    lc_render_desc rd;
    int target_set;
    lc_target target;
    int threads;
    const char *tf;
    float tau;
    lc_vec3 background;
    int alpha, stats, quiet, progress;
    grid_opts grid; /* volume inputs: cmd_render_grid.c */
} ropts;

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

/* Returns 0 ok, 1 help printed, -1 usage error (message printed). */
static int parse(ropts *o, int argc, char **argv, int want_input)
{
    o->rd.width = o->rd.height = 1024;
    o->progress = isatty(2);
    int camera_set = 0, gflag;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
#define VAL()                                                                                                          \
    do {                                                                                                               \
        if (!(v = arg_value(o->cmd, argc, argv, &i))) return -1;                                                       \
    } while (0)
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(render_help, stdout);
            fputs(grid_render_help, stdout);
            return 1;
        } else if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
            VAL();
            o->output = v;
        } else if (!strcmp(a, "--raw-particles")) {
            VAL();
            if (arg_size_t(o->cmd, a, v, &o->load.raw_count)) return -1;
            o->load.format = LC_PFORMAT_RAW;
        } else if (!strcmp(a, "--radius")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->load.radius)) return -1;
        } else if (!strcmp(a, "--radius-scale")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->load.radius_scale)) return -1;
        } else if (!strcmp(a, "--fields")) {
            VAL();
            if (!strcmp(v, "element")) o->load.fields_by_element = 1;
            else if (!strcmp(v, "none")) o->load.fields_by_element = 0;
            else {
                fprintf(stderr, "%s: --fields: '%s' is not none or element\n", o->cmd, v);
                return -1;
            }
        } else if (!strcmp(a, "--drop-invalid")) {
            o->load.drop_invalid = 1;
        } else if (!strcmp(a, "--leaf")) {
            VAL();
            if (arg_int(o->cmd, a, v, 1, 32, &o->load.leaf_size)) return -1;
        } else if (!strcmp(a, "--size")) {
            VAL();
            if (arg_size(o->cmd, a, v, &o->rd.width, &o->rd.height)) return -1;
        } else if (!strcmp(a, "--eye")) {
            VAL();
            if (arg_vec3(o->cmd, a, v, &o->rd.camera.eye)) return -1;
            camera_set |= 1;
        } else if (!strcmp(a, "--at")) {
            VAL();
            if (arg_vec3(o->cmd, a, v, &o->rd.camera.at)) return -1;
            camera_set |= 2;
        } else if (!strcmp(a, "--up")) {
            VAL();
            if (arg_vec3(o->cmd, a, v, &o->rd.camera.up)) return -1;
        } else if (!strcmp(a, "--fov")) {
            VAL();
            if (arg_float(o->cmd, a, v, 0.01f, 179.0f, &o->rd.camera.fovy)) return -1;
        } else if (!strcmp(a, "--ortho")) {
            VAL();
            if (arg_float(o->cmd, a, v, 0.0f, 1e30f, &o->rd.camera.height)) return -1;
            o->rd.camera.projection = LC_ORTHOGRAPHIC;
        } else if (!strcmp(a, "--tf")) {
            VAL();
            o->tf = v;
        } else if (!strcmp(a, "--tau")) {
            VAL();
            if (arg_float(o->cmd, a, v, 0.0f, 1e30f, &o->tau)) return -1;
        } else if (!strcmp(a, "--range")) {
            VAL();
            if (arg_pair(o->cmd, a, v, o->rd.range)) return -1;
            if (!(o->rd.range[1] > o->rd.range[0])) {
                fprintf(stderr, "%s: --range: expected LO < HI, got '%s'\n", o->cmd, v);
                return -1;
            }
        } else if (!strcmp(a, "--dt")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->rd.dt)) return -1;
        } else if (!strcmp(a, "--sigma")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-3f, 100.0f, &o->rd.particle.sigma)) return -1;
        } else if (!strcmp(a, "--kappa")) {
            VAL();
            if (arg_float(o->cmd, a, v, -1e30f, 1e30f, &o->rd.particle.kappa)) return -1;
            if (o->rd.particle.kappa == 0.0f) {
                fprintf(stderr, "%s: --kappa: 0 would make every value zero\n", o->cmd);
                return -1;
            }
        } else if (!strcmp(a, "--shade")) {
            o->rd.shading = LC_SHADE_DIFFUSE;
            if (i + 1 < argc && argv[i + 1][0] != '-') {
                const char *m = argv[i + 1];
                if (!strcmp(m, "none")) o->rd.shading = LC_SHADE_NONE, i++;
                else if (!strcmp(m, "diffuse")) o->rd.shading = LC_SHADE_DIFFUSE, i++;
                else if (!strcmp(m, "phong")) o->rd.shading = LC_SHADE_PHONG, i++;
            }
        } else if (!strcmp(a, "--alpha-stop")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-6f, 1.0f, &o->rd.alpha_stop)) return -1;
        } else if (!strcmp(a, "--background")) {
            VAL();
            if (arg_vec3(o->cmd, a, v, &o->background)) return -1;
        } else if (!strcmp(a, "--alpha")) {
            o->alpha = 1;
        } else if (!strcmp(a, "--spheres")) {
            VAL();
            if (arg_float(o->cmd, a, v, 1e-3f, 100.0f, &o->rd.particle.sphere_scale)) return -1;
        } else if (!strcmp(a, "--method")) {
            VAL();
            if (parse_method(o, v)) return -1;
        } else if (!strcmp(a, "--packet")) {
            VAL();
            if (arg_int(o->cmd, a, v, 1, 64, &o->rd.packet)) return -1;
        } else if (!strcmp(a, "--buffer")) {
            VAL();
            if (arg_int(o->cmd, a, v, 1, 4096, &o->rd.particle.buffer_samples)) return -1;
        } else if (!strcmp(a, "--target")) {
            VAL();
            if (lc_target_from_name(v, &o->target) != LC_OK) {
                fprintf(stderr, "%s: --target: %s\n", o->cmd, lc_last_error());
                return -1;
            }
            o->target_set = 1;
        } else if (!strcmp(a, "--threads")) {
            VAL();
            if (arg_int(o->cmd, a, v, 1, 1024, &o->threads)) return -1;
        } else if (!strcmp(a, "--tile")) {
            VAL();
            if (arg_int(o->cmd, a, v, 1, 4096, &o->rd.tile)) return -1;
        } else if (!strcmp(a, "--stats")) {
            o->stats = 1;
        } else if (!strcmp(a, "--progress")) {
            o->progress = 1;
        } else if (!strcmp(a, "--quiet")) {
            o->quiet = 1;
        } else if ((gflag = grid_parse_flag(&o->grid, o->cmd, argc, argv, &i)) != 0) {
            if (gflag < 0) return -1;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", o->cmd, a, o->cmd);
            return -1;
        } else if (want_input && !o->input) {
            o->input = a;
        } else {
            fprintf(stderr, "%s: unexpected argument '%s'\n", o->cmd, a);
            return -1;
        }
#undef VAL
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
    if (o->quiet) o->progress = 0;
    return 0;
}

static void progress(void *user, float f)
{
    (void)user;
    fprintf(stderr, "\rrendering %3d%%", (int)(100.0f * f + 0.5f));
    if (f >= 1.0f) fputc('\n', stderr);
}

/* The procedural demo: a double helix of "atoms" (field 0) inside a shell of
 * a second species (field 1), fixed seed. */
static lc_status demo_particles(lc_device *dev, lc_particles **out)
{
    enum { NHELIX = 4000, NSHELL = 6000 };
    static float xyz[3 * (NHELIX + NSHELL)], r[NHELIX + NSHELL];
    static uint8_t field[NHELIX + NSHELL];
    uint32_t seed = 12345u;
#define RND() ((seed = seed * 1664525u + 1013904223u), (float)(seed >> 8) / 16777216.0f)
    for (int i = 0; i < NHELIX; i++) {
        float s = (float)(i / 2) / (NHELIX / 2), ang = s * 6.0f * 6.2831853f + (i & 1) * 3.14159265f;
        xyz[3 * i] = 6.0f * cosf(ang) + 0.6f * (RND() - 0.5f);
        xyz[3 * i + 1] = -20.0f + 40.0f * s;
        xyz[3 * i + 2] = 6.0f * sinf(ang) + 0.6f * (RND() - 0.5f);
        r[i] = 0.7f;
        field[i] = 0;
    }
    for (int i = NHELIX; i < NHELIX + NSHELL; i++) {
        float u = 2.0f * RND() - 1.0f, ph = 6.2831853f * RND(), rad = 14.0f + 2.0f * RND();
        float sx = sqrtf(1.0f - u * u);
        xyz[3 * i] = rad * sx * cosf(ph);
        xyz[3 * i + 1] = 1.6f * rad * u;
        xyz[3 * i + 2] = rad * sx * sinf(ph);
        r[i] = 0.5f + 0.5f * RND();
        field[i] = 1;
    }
#undef RND
    lc_particles_desc d = {.count = NHELIX + NSHELL, .positions = xyz, .radii = r, .fields = field, .nfields = 2};
    return lc_particles_create(dev, &d, out);
}

static int run(ropts *o, int demo)
{
    int rc = CLI_EXIT_FAIL;
    lc_device *dev = NULL;
    lc_particles *parts = NULL;
    lc_grid *grid = NULL;
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
    double t0 = 0;
    struct timespec ts0, ts1;
    clock_gettime(CLOCK_MONOTONIC, &ts0);
    /* ---- volumes (cmd_render_grid.c): own loading, TF default and stats */
    lc_particles_info pi;
    memset(&pi, 0, sizeof pi);
    lc_grid_info gi;
    double load_s = 0;
    int volume = !demo && grid_is_volume(&o->grid, o->input);
    lc_status s;
    if (volume) {
        s = grid_load(dev, &o->grid, o->input, &grid, &gi);
        if (s != LC_OK) goto fail;
        clock_gettime(CLOCK_MONOTONIC, &ts1);
        load_s = (double)(ts1.tv_sec - ts0.tv_sec) + 1e-9 * (double)(ts1.tv_nsec - ts0.tv_nsec);
        o->rd.grid = grid;
        grid_apply(&o->grid, &o->rd);
        /* presets: peak extinction so the densest material stops a ray in about 1/8 of the diagonal */
        float dx = gi.bounds.hi.x - gi.bounds.lo.x, dy = gi.bounds.hi.y - gi.bounds.lo.y, dz = gi.bounds.hi.z - gi.bounds.lo.z;
        float tau = o->tau > 0.0f ? o->tau : 8.0f / sqrtf(dx * dx + dy * dy + dz * dz);
        if (o->tf && !strchr(o->tf, '.') && !strchr(o->tf, '/')) s = lc_tf_preset(dev, o->tf, 1, tau, &tf);
        else if (o->tf) s = lc_tf_load(dev, o->tf, &tf);
        else s = lc_tf_preset(dev, "heat", 1, tau, &tf);
        if (s != LC_OK) goto fail;
        goto render;
    }
    s = demo ? demo_particles(dev, &parts) : lc_particles_load(dev, o->input, &o->load, &parts);
    if (s != LC_OK) goto fail;
    clock_gettime(CLOCK_MONOTONIC, &ts1);
    load_s = (double)(ts1.tv_sec - ts0.tv_sec) + 1e-9 * (double)(ts1.tv_nsec - ts0.tv_nsec);
    lc_particles_get_info(parts, &pi);
    if (demo && !o->tf) {
        /* the helix warm and dense, the shell a faint cool haze */
        static const float warm[] = {0.0f, 0.7f, 0.15f, 0.05f, 0.5f, 1.0f, 0.55f, 0.1f, 1.0f, 1.0f, 0.95f, 0.7f};
        static const float cool[] = {0.0f, 0.1f, 0.3f, 0.8f, 1.0f, 0.5f, 0.85f, 1.0f};
        static const float op0[] = {0.0f, 0.0f, 0.15f, 0.0f, 0.6f, 3.0f, 1.0f, 6.0f};
        static const float op1[] = {0.0f, 0.0f, 0.2f, 0.0f, 1.0f, 0.18f};
        lc_tf_field f[2] = {{warm, 4 - 1, op0, 4, 1, {0.0f, 1.0f}}, {cool, 2, op1, 3, 1, {0.0f, 1.0f}}};
        s = lc_tf_create(dev, f, 2, &tf);
    } else if (o->tf && !strchr(o->tf, '.') && !strchr(o->tf, '/')) {
        float tau = o->tau > 0.0f ? o->tau : (pi.max_radius > 0.0f ? 1.0f / pi.max_radius : 1.0f);
        s = lc_tf_preset(dev, o->tf, pi.nfields, tau, &tf);
    } else if (o->tf) {
        s = lc_tf_load(dev, o->tf, &tf);
    } else {
        float tau = o->tau > 0.0f ? o->tau : (pi.max_radius > 0.0f ? 1.0f / pi.max_radius : 1.0f);
        s = lc_tf_preset(dev, demo || pi.nfields > 1 ? "demo" : "heat", pi.nfields, tau, &tf);
    }
    if (s != LC_OK) goto fail;
    o->rd.particles = parts;
render:
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
    t0 = st.seconds;
    lc_image_desc id = {o->rd.width, o->rd.height, rgba, o->background, o->alpha};
    s = lc_image_write(dev, o->output, &id);
    if (s != LC_OK) goto fail;
    if (!o->quiet) printf("wrote %s (%dx%d)\n", o->output, o->rd.width, o->rd.height);
    if (o->stats) {
        printf("target        %s (%d lanes), %d threads\n", lc_target_name(st.target), lc_target_lanes(st.target),
               st.threads);
        if (volume) grid_print_stats(&gi, stdout);
        else printf("particles     %zu (%zu dropped), %d fields, radius %.4g..%.4g\n", pi.count, pi.dropped, pi.nfields,
               (double)pi.min_radius, (double)pi.max_radius);
        if (!volume) {
            printf("load          %.3f s (reading and BVH build)\n", load_s);
            printf("bvh           %d nodes, depth %d, %.2f MB, build %.3f s; particle data %.2f MB\n", pi.bvh_nodes,
                   pi.bvh_depth, (double)pi.bvh_bytes / 1e6, pi.build_seconds, (double)pi.data_bytes / 1e6);
        } else {
            printf("load          %.3f s (reading, bricking and BVH build)\n", load_s);
        }
        printf("render        %.3f s (%.2f fps)\n", t0, 1.0 / t0);
        printf("rays          %llu\n", (unsigned long long)st.rays);
        printf("samples       %llu\n", (unsigned long long)st.samples);
        printf(volume ? "voxel samples %llu (%.1f M/s)\n" : "gaussians     %llu (%.1f M/s)\n", (unsigned long long)st.kernel_evals, (double)st.kernel_evals / t0 / 1e6);
        printf("nodes         %llu, leaves %llu, passes %llu\n", (unsigned long long)st.nodes,
               (unsigned long long)st.leaves, (unsigned long long)st.passes);
    }
    rc = 0;
    goto out;
fail:
    fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
out:
    free(rgba);
    lc_tf_destroy(tf);
    lc_particles_destroy(parts);
    lc_grid_destroy(grid);
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
