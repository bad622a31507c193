/* lanecast bench: one benchmark over the public API (after dav1d's checkasm:
 * every target is checked against the scalar target's image, then timed).
 * The case matrix is the cross product of the lists given; one JSON line per
 * case and target (bench/report.py turns them into docs/BENCHMARKS.md). */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "args.h"
#include "bench_run.h"
#include "cli.h"

#define CMD "lanecast bench"
#define MAXL 32

static const char help[] =
    "usage: lanecast bench [options]\n"
    "\n"
    "Checks every SIMD target against the scalar target's image (SPEC.md tolerances, alpha_stop 1)\n"
    "and times it, over a matrix of cases; prints one JSON line per case and target (stdout or -o).\n"
    "Targets are timed in interleaved rounds (order rotating) so load drift falls on all alike.\n"
    "\n"
    "matrix (comma lists; every combination is a case):\n"
    "  --scenes LIST     default uniform:1e5,heavy:1e5,cluster:1e5,1tii,grid:256,engine,rbf:1e4\n"
    "%s"
    "  --views LIST      far, medium, close (default far)\n"
    "  --sizes LIST      image sides or WxH (default 512)\n"
    "  --targets LIST    scalar, sse4, avx2, avx512_8, avx512 (default: every one this CPU runs)\n"
    "  --threads LIST    worker threads (default 1)\n"
    "  --methods LIST    default, coherent (particles, RBF sets), direct (particles), bvh, brute (grids, RBF sets);\n"
    "                    a method another kind lacks is skipped for it (default: default)\n"
    "  --modes LIST      dvr, mip, iso, slice (default dvr; iso at the middle of the value range,\n"
    "                    slice through the centre, normal z)\n"
    "  --packet LIST     packet sides in rays, 1 = lane-width (default 8)\n"
    "  --shading LIST    none, diffuse, phong (default none)\n"
    "  --alpha-stop LIST early-termination opacities in (0, 1] (default: the library's, 0.97)\n"
    "  --sigma LIST      particle truncation radii in r_i (default: the library's, 2)\n"
    "\n"
    "timing:\n"
    "  --warmup N        untimed rounds first (default 1)\n"
    "  --repeats N       at most N timed rounds (default 9, at most 256)\n"
    "  --min-repeats N   at least N timed rounds (default 3)\n"
    "  --seconds S       stop after S seconds of timed rounds once min-repeats are done (default 10)\n"
    "  --check-size N    side of the check images (default 128); --no-check skips the check\n"
    "\n"
    "other:\n"
    "  -o FILE           append the records to FILE (default stdout)\n"
    "  --data DIR        the shared data folder (default %s)\n"
    "  --quick           smoke run: a few tiny cases on every target, in seconds\n"
    "  --roofline        only measure this machine's ceilings per target (FMA peak, Gaussian\n"
    "                    micro-kernel, gathers vs scalar loads) and print them\n"
    "  --roof-seconds S  time per roofline kernel (default 0.3; case records carry the fraction\n"
    "                    of these ceilings they reach)\n"
    "  --width-study     targets avx2, avx512_8, avx512 (instruction set vs width), interleaved\n"
    "  --baseline EXE    A/B: this build against another build's lanecast EXE on the same cases, in\n"
    "                    interleaved rounds; one \"ab\" record per case: ratio baseline / this of the\n"
    "                    median frame time (wall and CPU), median, min and max over the rounds\n"
    "  --ab-rounds N     rounds of --baseline (default 5)\n"
    "  --jobs N          interactive timings instead (records \"job\"): full frame, navigation frame\n"
    "                    (pixel_scale 2), a render job's preview and refined image, and the latency of\n"
    "                    N cancels at random points of a frame (median, p95, worst)\n"
    "  --profile         grid stage profile instead (records \"profile\"): CPU time of fetch,\n"
    "                    interpolation, classification, shading, blending and the sample loop, from\n"
    "                    kernel variants with one more stage replaced each (built for %s)\n"
    "  --builders LIST   every scene (particle sets) once per BVH builder: %s\n"
    "                    (scene/builder:NAME; records carry build_s and build_peak_kb)\n"
    "  --resample LIST   particles through deposited grids instead (records \"resample\"; issue 28):\n"
    "                    the exact frame, then per grid side N the deposition to N^3 nodes over the\n"
    "                    set's bounds (median time, bytes), the grid renderer's frame of it with the\n"
    "                    same camera, TF and range, and its PSNR against the exact frame\n"
    "  --read FILE       trajectory reading rates instead (record \"read\"; .xtc, .trr, .dcd):\n"
    "                    frames counted, every frame in order, the middle one, frame 0; best of --repeats\n"
    "  --composite       data-parallel compositing alone, under mpiexec -np P (records \"mpi_composite\"):\n"
    "                    random full-frame images of each --composite-sizes side (default\n"
    "                    1,64,128,256,512,1024,2048) composited --repeats times in random orders: median\n"
    "                    of the slowest rank, steps, bytes and messages per rank against binary swap's\n"
    "                    S (1 - 1/P), S = 16 W H\n"
    "  --blend           the compositing's blend and pack throughput at 1024^2 (one process)\n"
    "  --imbalance       every --scenes scene split into the kd regions of P = 2 .. 64 ranks, each\n"
    "                    region rendered in turn at 256^2 (one process): slowest against mean\n"
    "\n"
    "examples:\n"
    "  lanecast bench --quick\n"
    "  lanecast bench --scenes uniform:1e4,uniform:1e5,uniform:1e6 --threads 1,2 -o bench/results/p.jsonl\n"
    "  lanecast bench --scenes uniform:1e5 --alpha-stop 0.9,0.95,0.97,0.99,1 --targets avx512\n"
    "  lanecast bench --roofline\n"
    "  lanecast bench --width-study --scenes uniform:1e5,grid:256\n"
    "  lanecast bench --baseline ../before/build/tools/lanecast --scenes 1tw7,engine --threads 1\n"
    "  lanecast bench --jobs 200 --scenes engine,1tw7,uniform:1e6 --sizes 1024 --threads 2 --targets avx2\n"
    "  lanecast bench --profile --scenes engine,grid:512 --sizes 1024 --shading none,phong --targets avx2\n"
    "  lanecast bench --builders embree,sah --scenes uniform:1e6,1tw7 --views far,close --targets avx2\n"
    "  mpiexec -np 2 lanecast bench --composite --repeats 15\n"
    "  lanecast bench --scenes engine,engine/bricked,engine/no-heuristics,rbf:1e4,rbf:1e4/octree:16\n"
    "  lanecast bench --read adk1000.xtc --repeats 2\n"
    "  lanecast bench --resample 128,256,512 --scenes cluster:1e6,1tw7 --threads 2 --targets avx2 --sizes 1024\n"
    "\n"
    "exit status: 0 ok, 1 a check or render failed (the records say which), 2 bad usage\n";

typedef struct list {
    int n;
    char *v[MAXL];
} list;

typedef struct opts {
    list scenes, views, sizes, targets, threads, methods, modes, packets, shadings, alphas, sigmas, builders, resample;
    int resample_n[MAXL]; /* --resample: grid sides */
    int warmup, repeats, min_repeats, check_size, quick, roofline, width_study, jobs, ab_rounds, profile;
    int composite, blend, imbalance;
    double seconds, roof_seconds;
    const char *out, *data, *baseline, *read, *csizes;
    char *pass[256]; /* the flags a --baseline run passes on (all but -o, --baseline, --ab-rounds) */
    int npass;
} opts;

static int split(list *l, const char *flag, const char *s)
{
    char *c = strdup(s);
    l->n = 0;
    if (!c) return -1;
    for (char *t = strtok(c, ","); t; t = strtok(NULL, ",")) {
        if (l->n == MAXL) {
            fprintf(stderr, CMD ": %s: more than %d values\n", flag, MAXL);
            return -1;
        }
        l->v[l->n++] = t;
    }
    if (!l->n) fprintf(stderr, CMD ": %s: an empty list\n", flag);
    return l->n ? 0 : -1;
}

static const char *const method_names[] = {"default", "coherent", "direct", "bvh", "brute"};
static const char *const mode_names[] = {"dvr", "mip", "iso", "slice"};
static const char *const shading_names[] = {"none", "diffuse", "phong"};

static int name_index(const char *const *names, int n, const char *s)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(names[i], s)) return i;
    return -1;
}

/* Every list value checked before any work. */
static int validate(opts *o)
{
    for (int i = 0; i < o->builders.n; i++) {
        int k = 0;
        while (bench_builders[k] && strcmp(bench_builders[k], o->builders.v[i])) k++;
        if (!bench_builders[k]) {
            fprintf(stderr, CMD ": --builders: unknown builder '%s' (see lanecast bench --help)\n", o->builders.v[i]);
            return -1;
        }
    }
    for (int i = 0; i < o->scenes.n; i++)
        if (!bench_scene_known(o->scenes.v[i])) {
            fprintf(stderr, CMD ": --scenes: unknown scene '%s' (see lanecast bench --help)\n", o->scenes.v[i]);
            return -1;
        }
    for (int i = 0; i < o->views.n; i++)
        if (strcmp(o->views.v[i], "far") && strcmp(o->views.v[i], "medium") && strcmp(o->views.v[i], "close")) {
            fprintf(stderr, CMD ": --views: '%s' is not far, medium or close\n", o->views.v[i]);
            return -1;
        }
    int w, h, x;
    float f;
    lc_target t;
    for (int i = 0; i < o->sizes.n; i++) {
        if (strchr(o->sizes.v[i], 'x') ? arg_size(CMD, "--sizes", o->sizes.v[i], &w, &h)
                                       : arg_int(CMD, "--sizes", o->sizes.v[i], 1, LC_MAX_IMAGE_SIDE, &w))
            return -1;
    }
    if (o->csizes) {
        list cs = {0};
        split(&cs, "", o->csizes);
        for (int i = 0; i < cs.n; i++)
            if (arg_int(CMD, "--composite-sizes", cs.v[i], 1, 8192, &x)) return -1;
    }
    for (int i = 0; i < o->targets.n; i++)
        if (lc_target_from_name(o->targets.v[i], &t) != LC_OK || t == LC_TARGET_AUTO) {
            fprintf(stderr, CMD ": --targets: '%s' is not scalar, sse4, avx2, avx512_8 or avx512\n", o->targets.v[i]);
            return -1;
        }
    for (int i = 0; i < o->threads.n; i++)
        if (arg_int(CMD, "--threads", o->threads.v[i], 1, 1024, &x)) return -1;
    for (int i = 0; i < o->resample.n; i++)
        if (arg_int(CMD, "--resample", o->resample.v[i], 2, 4096, &o->resample_n[i])) return -1;
    for (int i = 0; i < o->packets.n; i++)
        if (arg_int(CMD, "--packet", o->packets.v[i], 1, 64, &x)) return -1;
    for (int i = 0; i < o->alphas.n; i++)
        if (arg_float(CMD, "--alpha-stop", o->alphas.v[i], 1e-6f, 1.0f, &f)) return -1;
    for (int i = 0; i < o->sigmas.n; i++)
        if (arg_float(CMD, "--sigma", o->sigmas.v[i], 0.01f, 100.0f, &f)) return -1;
    const struct {
        const list *l;
        const char *flag;
        const char *const *names;
        int n;
    } named[] = {{&o->methods, "--methods", method_names, 5}, {&o->modes, "--modes", mode_names, 4},
                 {&o->shadings, "--shading", shading_names, 3}};
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < named[k].l->n; i++)
            if (name_index(named[k].names, named[k].n, named[k].l->v[i]) < 0) {
                fprintf(stderr, CMD ": %s: unknown value '%s' (see lanecast bench --help)\n", named[k].flag,
                        named[k].l->v[i]);
                return -1;
            }
    return 0;
}

/* method index -> lc_method for a kind, or -1 when the kind lacks it */
static int method_for(lc_kind kind, int m)
{
    if (m == 0) return LC_METHOD_DEFAULT;
    if (kind == LC_KIND_PARTICLES) return m == 1 ? LC_METHOD_COHERENT : m == 2 ? LC_METHOD_DIRECT : -1;
    if (kind == LC_KIND_RBF && m == 1) return LC_METHOD_COHERENT; /* RBF sets: coherent, bvh, brute */
    return m == 3 ? LC_METHOD_BVH : m == 4 ? LC_METHOD_BRUTE : -1;
}

/* Devices are kept per target and thread count for the whole run. */
typedef struct devcache {
    lc_device *dev[LC_TARGET_COUNT][MAXL];
} devcache;

static lc_device *device_for(devcache *c, lc_target t, int ti, int threads)
{
    if (!c->dev[t][ti] && lc_device_create(&(lc_device_desc){.target = t, .threads = threads}, &c->dev[t][ti]) != LC_OK) {
        fprintf(stderr, CMD ": device %s with %d threads: %s\n", lc_target_name(t), threads, lc_last_error());
        return NULL;
    }
    return c->dev[t][ti];
}

static int parse_opts(int argc, char **argv, opts *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        int first = i;
        struct {
            const char *flag;
            list *l;
        } lists[] = {{"--scenes", &o->scenes},   {"--views", &o->views},     {"--sizes", &o->sizes},
                     {"--targets", &o->targets}, {"--threads", &o->threads}, {"--methods", &o->methods},
                     {"--modes", &o->modes},     {"--packet", &o->packets},  {"--shading", &o->shadings},
                     {"--alpha-stop", &o->alphas}, {"--sigma", &o->sigmas}, {"--builders", &o->builders},
                     {"--resample", &o->resample}};
        int done = 0;
        for (size_t k = 0; k < sizeof lists / sizeof lists[0] && !done; k++)
            if (!strcmp(a, lists[k].flag)) {
                if (!(v = arg_value(CMD, argc, argv, &i)) || split(lists[k].l, a, v)) return -1;
                done = 1;
            }
        if (done) goto pass_on;
        if (!strcmp(a, "--baseline")) {
            if (!(o->baseline = arg_value(CMD, argc, argv, &i))) return -1;
            continue;
        } else if (!strcmp(a, "--ab-rounds")) {
            if (!(v = arg_value(CMD, argc, argv, &i)) || arg_int(CMD, a, v, 1, 64, &o->ab_rounds)) return -1;
            continue;
        } else if (!strcmp(a, "-o")) {
            if (!(o->out = arg_value(CMD, argc, argv, &i))) return -1;
            continue;
        }
        if (!strcmp(a, "--quick")) o->quick = 1;
        else if (!strcmp(a, "--roofline")) o->roofline = 1;
        else if (!strcmp(a, "--width-study")) o->width_study = 1;
        else if (!strcmp(a, "--profile")) o->profile = 1;
        else if (!strcmp(a, "--composite")) o->composite = 1;
        else if (!strcmp(a, "--blend")) o->blend = 1;
        else if (!strcmp(a, "--imbalance")) o->imbalance = 1;
        else if (!strcmp(a, "--composite-sizes")) {
            if (!(o->csizes = arg_value(CMD, argc, argv, &i))) return -1;
        } else if (!strcmp(a, "--read")) {
            if (!(o->read = arg_value(CMD, argc, argv, &i))) return -1;
        }
        else if (!strcmp(a, "--no-check")) o->check_size = 0;
        else if (!strcmp(a, "--jobs")) {
            if (!(v = arg_value(CMD, argc, argv, &i)) || arg_int(CMD, a, v, 1, 100000, &o->jobs)) return -1;
        } else if (!strcmp(a, "--data")) {
            if (!(o->data = arg_value(CMD, argc, argv, &i))) return -1;
        } else if (!strcmp(a, "--warmup") || !strcmp(a, "--repeats") || !strcmp(a, "--min-repeats") ||
                   !strcmp(a, "--check-size")) {
            int *dst = a[2] == 'w' ? &o->warmup : a[2] == 'r' ? &o->repeats : a[2] == 'm' ? &o->min_repeats : &o->check_size;
            long lo = a[2] == 'r' || a[2] == 'c' ? 1 : 0, hi = a[2] == 'c' ? 4096 : BENCH_MAX_ROUNDS;
            if (!(v = arg_value(CMD, argc, argv, &i)) || arg_int(CMD, a, v, lo, hi, dst)) return -1;
        } else if (!strcmp(a, "--seconds") || !strcmp(a, "--roof-seconds")) {
            float s;
            if (!(v = arg_value(CMD, argc, argv, &i)) || arg_float(CMD, a, v, 0.0f, 1e6f, &s)) return -1;
            *(a[2] == 's' ? &o->seconds : &o->roof_seconds) = s;
        } else {
            fprintf(stderr, CMD ": unknown option '%s' (see lanecast bench --help)\n", a);
            return -1;
        }
    pass_on:
        for (int k = first; k <= i && o->npass < 256; k++) o->pass[o->npass++] = argv[k];
    }
    return 0;
}

/* Targets to time: the ones named (those this CPU lacks are skipped with a
 * note), or every supported one. */
static int pick_targets(const opts *o, lc_target *out)
{
    int n = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        int named = 0;
        for (int i = 0; i < o->targets.n; i++) named |= !strcmp(o->targets.v[i], tn);
        if (o->targets.n && !named) continue;
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            if (named) fprintf(stderr, CMD ": note: target %s skipped: not compiled in or not supported here\n", tn);
            continue;
        }
        out[n++] = (lc_target)t;
    }
    return n;
}

typedef struct run {
    const opts *o;
    devcache *dc;
    lc_target targets[LC_TARGET_COUNT];
    int ntargets, cpus;
    const bench_roof *roof;
    lc_tf *tf;
    FILE *out;
    int bad, cases;
} run;

/* The innermost loops of one scene and view: size, mode, method, packet,
 * shading, alpha_stop, sigma, threads. */
static void run_view(run *R, bench_scene *sc, const char *view)
{
    const opts *o = R->o;
    lc_camera cam;
    if (bench_view_camera(sc, view, &cam)) {
        fprintf(stderr, CMD ": %s: no camera for view %s\n", sc->name, view);
        R->bad++;
        return;
    }
    int nsig = sc->kind == LC_KIND_PARTICLES && o->sigmas.n ? o->sigmas.n : 1;
    int nalpha = o->alphas.n ? o->alphas.n : 1;
    for (int si = 0; si < o->sizes.n; si++)
        for (int mo = 0; mo < o->modes.n; mo++)
            for (int me = 0; me < o->methods.n; me++) {
                int method = method_for(sc->kind, name_index(method_names, 5, o->methods.v[me]));
                if (method < 0) continue;
                for (int pk = 0; pk < o->packets.n; pk++)
                    for (int sh = 0; sh < o->shadings.n; sh++)
                        for (int al = 0; al < nalpha; al++)
                            for (int sg = 0; sg < nsig; sg++)
                                for (int th = 0; th < o->threads.n; th++) {
                                    bench_group g = {.scene = sc, .view = view, .mode_name = o->modes.v[mo],
                                                     .method_name = o->methods.v[me], .shading_name = o->shadings.v[sh],
                                                     .study = o->width_study ? "width" : "", .cpus = R->cpus,
                                                     .ntargets = R->ntargets, .check_size = o->check_size,
                                                     .warmup = o->warmup, .min_rounds = o->min_repeats,
                                                     .max_rounds = o->repeats, .seconds = o->seconds, .roof = R->roof,
                                                     .machine = bench_machine_json(), .out = R->out};
                                    const char *sz = o->sizes.v[si];
                                    if (strchr(sz, 'x')) arg_size(CMD, "--sizes", sz, &g.width, &g.height);
                                    else g.height = g.width = atoi(sz);
                                    g.packet = atoi(o->packets.v[pk]), g.threads = atoi(o->threads.v[th]);
                                    g.alpha_stop = o->alphas.n ? (float)atof(o->alphas.v[al]) : 0;
                                    g.sigma = sc->kind == LC_KIND_PARTICLES && o->sigmas.n ? (float)atof(o->sigmas.v[sg]) : 0;
                                    int ok = 1;
                                    for (int i = 0; i < R->ntargets; i++) {
                                        g.targets[i] = R->targets[i];
                                        ok &= (g.devs[i] = device_for(R->dc, R->targets[i], th, g.threads)) != NULL;
                                    }
                                    ok &= (g.scalar_dev = device_for(R->dc, LC_TARGET_SCALAR, th, g.threads)) != NULL;
                                    if (!ok) {
                                        R->bad++;
                                        continue;
                                    }
                                    if (sc->kind == LC_KIND_PARTICLES) {
                                        lc_particle_params pp = {.sigma = g.sigma};
                                        lc_particles_set_params(sc->vol, &pp);
                                    }
                                    const float *rg = sc->info.range;
                                    lc_vec3 c = cam.at;
                                    lc_render_desc d = {.width = g.width, .height = g.height, .camera = cam, .tf = R->tf,
                                                        .volume = sc->vol, .mode = (lc_mode)name_index(mode_names, 4, g.mode_name),
                                                        .iso = 0.5f * (rg[0] + rg[1]), .nplanes = 1,
                                                        .planes = {{.point = c, .normal = {0, 0, 1}}},
                                                        .alpha_stop = g.alpha_stop,
                                                        .shading = (lc_shading)name_index(shading_names, 3, g.shading_name),
                                                        .method = (lc_method)method, .packet = g.packet};
                                    fprintf(stderr, CMD ": %s %s %dx%d %s %s packet %d %s threads %d ...\n", sc->name, view,
                                            g.width, g.height, g.mode_name, g.method_name, g.packet, g.shading_name,
                                            g.threads);
                                    R->bad += o->jobs       ? bench_job_group(&g, &d, o->jobs)
                                              : o->profile  ? bench_profile_group(&g, &d)
                                              : o->resample.n ? bench_resample_group(&g, &d, o->resample_n, o->resample.n)
                                                            : bench_run_group(&g, &d);
                                    R->cases++;
                                }
            }
}

static void run_scene(run *R, lc_device *build_dev, const char *name)
{
    bench_scene sc;
    char note[1024] = "";
    fprintf(stderr, CMD ": building %s ...\n", name);
    lc_status s = bench_scene_make(build_dev, name, R->o->data, &sc, note, sizeof note);
    if (s != LC_OK) {
        fprintf(stderr, CMD ": %s%s\n", sc.absent ? "note: " : "", note);
        fprintf(R->out, "{\"record\": \"skip\", \"scene\": ");
        bench_json_str(R->out, name);
        fprintf(R->out, ", \"note\": ");
        bench_json_str(R->out, note);
        fprintf(R->out, ", %s}\n", bench_machine_json());
        if (!sc.absent) R->bad++;
        return;
    }
    if (lc_tf_auto(build_dev, sc.vol, NULL, 0, &R->tf) != LC_OK) {
        fprintf(stderr, CMD ": %s: default TF: %s\n", name, lc_last_error());
        R->bad++;
    } else
        for (int v = 0; v < R->o->views.n; v++) run_view(R, &sc, R->o->views.v[v]);
    lc_tf_destroy(R->tf);
    R->tf = NULL;
    bench_scene_free(&sc);
}

/* --quick and --width-study fill in what was not given. */
static void apply_presets(opts *o)
{
    static char q_scenes[] = "uniform:2000,heavy:1000,cluster:1000,grid:24,rbf:200,neghip";
    static char d_scenes[] = "uniform:1e5,heavy:1e5,cluster:1e5,1tii,grid:256,engine,rbf:1e4";
    static char w_targets[] = "avx2,avx512_8,avx512", one[] = "1", far[] = "far", dvr[] = "dvr", def[] = "default",
                eight[] = "8", none[] = "none", q_size[] = "40", d_size[] = "512";
    if (o->quick) {
        if (!o->scenes.n) split(&o->scenes, "", q_scenes);
        if (!o->sizes.n) split(&o->sizes, "", q_size);
        o->repeats = 2, o->min_repeats = 1, o->seconds = 1, o->roof_seconds = 0.01;
        if (o->check_size > 64) o->check_size = 40;
    }
    if (o->width_study && !o->targets.n) split(&o->targets, "", w_targets);
    struct {
        list *l;
        char *def;
    } d[] = {{&o->scenes, d_scenes}, {&o->sizes, d_size}, {&o->views, far},     {&o->threads, one},
             {&o->methods, def},     {&o->modes, dvr},    {&o->packets, eight}, {&o->shadings, none}};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        if (!d[i].l->n) split(d[i].l, "", d[i].def);
}

int cli_bench(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            char builders[256] = "";
            for (int k = 0; bench_builders[k]; k++) {
                size_t l = strlen(builders);
                snprintf(builders + l, sizeof builders - l, "%s%s", k ? ", " : "", bench_builders[k]);
            }
            printf(help, bench_scene_help, LC_BENCH_DATA_DIR, bench_profile_targets(), builders);
            return 0;
        }
    static opts o = {.warmup = 1, .repeats = 9, .min_repeats = 3, .check_size = 128, .seconds = 10, .roof_seconds = 0.3,
                     .data = LC_BENCH_DATA_DIR};
    if (parse_opts(argc, argv, &o)) return CLI_EXIT_USAGE;
    apply_presets(&o);
    if (validate(&o)) return CLI_EXIT_USAGE;
    if (o.min_repeats > o.repeats) o.min_repeats = o.repeats;
    FILE *out = stdout;
    if (o.out && !(out = fopen(o.out, "a"))) {
        fprintf(stderr, CMD ": -o %s: cannot open for appending\n", o.out);
        return CLI_EXIT_FAIL;
    }
    if (o.baseline) {
        /* as many timed frames in every run, so whole runs do the same work */
        static char minr[16];
        snprintf(minr, sizeof minr, "%d", o.repeats);
        if (o.npass < 254) o.pass[o.npass++] = "--min-repeats", o.pass[o.npass++] = minr;
        int rc = bench_ab(o.baseline, o.ab_rounds ? o.ab_rounds : 5, o.pass, o.npass, out);
        if (out != stdout && fclose(out)) rc = 1;
        return rc ? CLI_EXIT_FAIL : 0;
    }
    if (o.composite || o.blend || o.imbalance) {
        int rounds = o.quick ? 1 : o.repeats;
        int rc = o.composite ? bench_composite(rounds, o.csizes ? o.csizes : "1,64,128,256,512,1024,2048", out)
                 : o.blend   ? bench_blend(rounds, out)
                             : bench_imbalance(o.scenes.n, o.scenes.v, o.data, out);
        if (out != stdout && fclose(out)) rc = 1;
        return rc ? CLI_EXIT_FAIL : 0;
    }
    if (o.read) {
        int rc = bench_read(o.read, o.quick ? 1 : o.repeats, out);
        if (out != stdout && fclose(out)) rc = 1;
        return rc == 2 ? CLI_EXIT_USAGE : rc ? CLI_EXIT_FAIL : 0;
    }
    bench_roof roof;
    fprintf(stderr, CMD ": measuring this machine's ceilings (%g s per kernel) ...\n", o.roof_seconds);
    bench_roof_measure(&roof, o.roof_seconds);
    if (o.roofline) {
        bench_roof_print(out, &roof, bench_machine_json());
        if (out != stdout) fclose(out);
        return 0;
    }
    run R = {.o = &o, .roof = &roof, .out = out, .cpus = (int)sysconf(_SC_NPROCESSORS_ONLN)};
    R.ntargets = pick_targets(&o, R.targets);
    static devcache dc;
    R.dc = &dc;
    int maxth = 1;
    for (int i = 0; i < o.threads.n; i++) maxth = atoi(o.threads.v[i]) > maxth ? atoi(o.threads.v[i]) : maxth;
    lc_device *build_dev = NULL;
    if (!R.ntargets || lc_device_create(&(lc_device_desc){.threads = maxth}, &build_dev) != LC_OK) {
        fprintf(stderr, CMD ": %s\n", R.ntargets ? lc_last_error() : "none of the targets asked for runs here");
        if (out != stdout) fclose(out);
        return CLI_EXIT_FAIL;
    }
    for (int i = 0; i < o.scenes.n; i++) {
        if (!o.builders.n) run_scene(&R, build_dev, o.scenes.v[i]);
        for (int b = 0; b < o.builders.n; b++) {
            char name[128];
            snprintf(name, sizeof name, "%s/builder:%s", o.scenes.v[i], o.builders.v[b]);
            run_scene(&R, build_dev, name);
        }
    }
    lc_device_destroy(build_dev);
    for (int t = 0; t < LC_TARGET_COUNT; t++)
        for (int k = 0; k < MAXL; k++) lc_device_destroy(dc.dev[t][k]);
    if (out != stdout && fclose(out)) {
        fprintf(stderr, CMD ": -o %s: write failed\n", o.out);
        return CLI_EXIT_FAIL;
    }
    fprintf(stderr, CMD ": %d case groups, %d failures%s\n", R.cases, R.bad,
            R.bad ? " (checks or renders: the records and the lines above say which)" : "");
    return R.bad ? CLI_EXIT_FAIL : 0;
}
