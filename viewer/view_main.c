/* lanecast view INPUT [options]: the command. It takes every input, camera,
 * TF and mode option of lanecast render (tools/render_opts.c parses them,
 * tools/cmd_render.c loads the data and builds the TF the same way), plus
 * its own options, which are taken out of argv first. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"
#include "cli.h"
#include "render_opts.h"
#include "view.h"


static const char view_help[] =
    "usage: lanecast view INPUT [options]\n"
    "       lanecast view --demo [options]\n"
    "\n"
    "A window that renders INPUT progressively (a preview pass, then the full image) and is\n"
    "explored with the mouse: the render runs on its own threads and the window always shows\n"
    "the latest finished pass. It takes every input, camera, TF and mode option of lanecast\n"
    "render (lanecast render --help), and renders what lanecast render renders with them.\n"
    "\n"
    "mouse and keys:\n"
    "  left drag             orbit about the view's centre (the --at point)\n"
    "  middle drag, shift + left drag   pan\n"
    "  wheel                 zoom\n"
    "  r                     reset the view\n"
    "  s                     save the refined frame as lanecast-view-NNN.png (never overwriting)\n"
    "  c                     print the camera as lanecast render flags (--eye --at --up --fov)\n"
    "  h                     hide or show the panels and the overlay\n"
    "  b                     the data's bounding box on or off\n"
    "  q, Esc                quit\n"
    "\n"
    "options (besides lanecast render's; -o, --orbit and --frames do not apply):\n"
    "  --size WxH            render at this size (the window opens at it); default: the\n"
    "                        window's framebuffer, which opens at 768x768\n"
    "  --demo                the built-in demo scene instead of INPUT\n"
    "  --nav-scale S         navigation quality: every S-th pixel while the camera moves (2..16,\n"
    "                        default 2; the smallest scale adaptation goes to)\n"
    "  --target-ms MS        the navigation frame time adaptation holds (default 50)\n"
    "  --no-adaptive         keep the navigation scale at --nav-scale\n"
    "  --refine-delay S      seconds from the mouse's release to the full frame (default 0)\n"
    "  --screenshot PATH     write the first fully refined frame to PATH and exit\n"
    "  --script FILE         replay commands, one a line, through the same code as the mouse,\n"
    "                        keys and panels: orbit DX DY, pan DX DY (pixels), zoom STEPS,\n"
    "                        key K, set NAME VALUE (a panel's value, clamped to its bounds: mode,\n"
    "                        shading, method, target, colormap, iso, dt, alpha_stop, sigma,\n"
    "                        kappa, ka, kd, ks, phong_exp, threads, field, plane_axis, plane_pos,\n"
    "                        range_lo, range_hi, opacity_scale, nav_scale, nav_step, target_ms,\n"
    "                        adaptive, refine_delay, box, panels), mode M [ISO], target T,\n"
    "                        tf FIELD INDEX V TAU (INDEX = the count adds a point),\n"
    "                        tf-delete FIELD INDEX, save-tf PATH, wait (for the refined frame),\n"
    "                        sleep S, screenshot PATH, camera, frame N, step N, play, pause, quit;\n"
    "                        for measurements: down X Y [shift|middle], move X Y, up (the mouse\n"
    "                        button), wait-frame (for the current job's end), stats (one line:\n"
    "                        its quality, time, samples)\n"
    "\n"
    "Over ssh: ssh -X HOST lanecast view FILE (an OpenGL 2.1 context, which X forwarding\n"
    "provides). Without a display it says so and exits 1; lanecast render writes images.\n"
    "\n"
    "examples:\n"
    "  lanecast view ../shared/data/volumes/engine.nhdr --shade phong\n"
    "  lanecast view 1tw7_solvated.pdb --size 512x512 --screenshot first.png\n"
    "\n"
    "exit status: 0 ok, 1 no display, bad input or failed work, 2 bad usage\n";

typedef struct view_opts {
    int demo, size_given, nav_scale, adaptive;
    float target_ms, refine_delay;
    const char *screenshot, *script;
} view_opts;

/* Takes lanecast view's own options out of argv (the rest goes to
 * render_parse); 0 ok, 1 help printed, -1 usage error. */
static int split_args(int argc, char **argv, view_opts *vo, int *rargc, char **rargv)
{
    const char *cmd = "lanecast view";
    *rargc = 0;
    rargv[(*rargc)++] = argv[0];
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *val;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(view_help, stdout);
            return 1;
        }
        if (!strcmp(a, "-o") || !strcmp(a, "--output") || !strcmp(a, "--orbit") || !strcmp(a, "--frames")) {
            fprintf(stderr, "%s: %s does not apply (s and --screenshot save images; lanecast render writes them)\n",
                    cmd, a);
            return -1;
        }
        if (!strcmp(a, "--demo")) vo->demo = 1;
        else if (!strcmp(a, "--no-adaptive")) vo->adaptive = 0;
        else if (!strcmp(a, "--screenshot") || !strcmp(a, "--script") || !strcmp(a, "--nav-scale") ||
                 !strcmp(a, "--target-ms") || !strcmp(a, "--refine-delay")) {
            if (!(val = arg_value(cmd, argc, argv, &i))) return -1;
            if (!strcmp(a, "--screenshot")) vo->screenshot = val;
            else if (!strcmp(a, "--script")) vo->script = val;
            else if (!strcmp(a, "--nav-scale")) {
                if (arg_int(cmd, a, val, 2, 16, &vo->nav_scale)) return -1;
            } else if (!strcmp(a, "--target-ms")) {
                if (arg_float(cmd, a, val, 1.0f, 1e6f, &vo->target_ms)) return -1;
            } else if (arg_float(cmd, a, val, 0.0f, 3600.0f, &vo->refine_delay)) {
                return -1;
            }
        } else {
            if (!strcmp(a, "--size")) vo->size_given = 1;
            rargv[(*rargc)++] = argv[i];
        }
    }
    rargv[*rargc] = NULL;
    if (vo->screenshot && lc_image_check(NULL, vo->screenshot) != LC_OK) {
        fprintf(stderr, "%s: --screenshot: %s\n", cmd, lc_last_error());
        return -1;
    }
    return 0;
}

/* The wanted state of the first frame: the render command's descriptor and TF. */
static void init_state(view_state *v, const ropts *o, const view_opts *vo, lc_volume *vol, lc_tf *tf)
{
    pthread_mutex_init(&v->mu, NULL);
    pthread_mutex_init(&v->vol_mu, NULL);
    pthread_cond_init(&v->cv, NULL);
    v->cmd = "lanecast view";
    const char *slash = vo->demo ? NULL : strrchr(o->input, '/');
    v->input = vo->demo ? "demo" : slash ? slash + 1 : o->input; /* the overlay and title show the file's name */
    v->volume = vol;
    v->initial_tf = tf;
    lc_volume_get_info(vol, &v->vinfo);
    v->want.rd = o->rd;
    v->want.rd.volume = NULL, v->want.rd.tf = NULL;
    v->want.rd.progress = NULL, v->want.rd.progress_user = NULL;
    v->home = o->rd.camera;
    view_tf_from(&v->want.tf, tf);
    if (lc_volume_kind(vol) == LC_KIND_PARTICLES) {
        lc_particles_info pi;
        if (lc_particles_get_info(vol, &pi) == LC_OK) v->want.pp = pi.params;
    }
    v->want.target = o->target_set ? o->target : LC_TARGET_AUTO;
    v->want.threads = o->threads;
    v->want.nav_scale = v->min_nav_scale = vo->nav_scale;
    v->want.nav_step = 1.0f;
    v->want.gen = 1;
    v->background = o->background;
    v->alpha = o->alpha;
    v->size_fixed = vo->size_given;
    v->adaptive = vo->adaptive;
    v->target_ms = vo->target_ms;
    v->refine_delay = vo->refine_delay;
    v->show_ui = 1;
    v->plane_pos = 0.5f, v->plane_axis = 2;
    v->frame = o->frame;
    v->frame_loading = -1;
}

static void log_warning(void *user, lc_log_level level, const char *msg)
{
    if (level == LC_LOG_WARNING) fprintf(stderr, "%s: warning: %s\n", (const char *)user, msg);
}

/* Loads the data as lanecast render does; 0 ok, else the exit status. */
static int load(ropts *o, const view_opts *vo, lc_device *dev, view_state *v, const cli_kind **kind_out)
{
    int usage = 0;
    int64_t frames = 1;
    const char *fopts = "";
    const cli_kind *kind =
        render_decide_kind(o, dev, vo->demo ? LC_KIND_PARTICLES : LC_KIND_NONE, &usage, &frames, &fopts);
    if (kind && !vo->demo && kind->defaults &&
        kind->defaults(o->cmd, &o->load, fopts, o->tf || o->colormap || o->nopacity))
        kind = NULL;
    if (!kind) return usage ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
    if (frames > 0 && o->frame >= frames) {
        fprintf(stderr, "%s: %s holds %lld frame%s (0 to %lld); frame %lld was asked for\n", o->cmd, o->input,
                (long long)frames, frames == 1 ? "" : "s", (long long)frames - 1, (long long)o->frame);
        return CLI_EXIT_FAIL;
    }
    if (vo->demo && o->rd.shading == LC_SHADE_NONE) o->rd.shading = LC_SHADE_PHONG;
    lc_volume *vol = NULL;
    lc_tf *tf = NULL;
    if (render_load(o, dev, vo->demo, kind, o->frame, &vol, &tf) != LC_OK ||
        render_view_camera(o, vol, 0, &o->rd.camera) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        lc_volume_destroy(vol);
        lc_tf_destroy(tf);
        return CLI_EXIT_FAIL;
    }
    init_state(v, o, vo, vol, tf);
    v->frames = frames;
    *kind_out = kind;
    return 0;
}

int cli_view(int argc, char **argv)
{
    view_opts vo = {.nav_scale = 2, .adaptive = 1, .target_ms = 50.0f};
    char **rargv = calloc((size_t)argc + 1, sizeof *rargv);
    ropts *o = calloc(1, sizeof *o);
    view_state *v = calloc(1, sizeof *v);
    int rargc = 0, rc = CLI_EXIT_USAGE;
    lc_device *dev = NULL, *ui_dev = NULL;
    view_script *script = NULL;
    if (!rargv || !o || !v) {
        fprintf(stderr, "lanecast view: out of memory\n");
        rc = CLI_EXIT_FAIL;
        goto out;
    }
    int p = split_args(argc, argv, &vo, &rargc, rargv);
    if (p) {
        rc = p > 0 ? 0 : CLI_EXIT_USAGE;
        goto out;
    }
    o->cmd = "lanecast view";
    o->output = "-"; /* render_parse wants one; the view saves through s and --screenshot */
    p = render_parse(o, rargc, rargv, !vo.demo);
    if (p) {
        rc = p > 0 ? 0 : CLI_EXIT_USAGE;
        goto out;
    }
    rc = CLI_EXIT_FAIL;
    const char *display = getenv("DISPLAY");
    if (!display || !display[0]) {
        fprintf(stderr, "lanecast view: no display (DISPLAY is not set); lanecast render writes images\n");
        goto out;
    }
    if (vo.script && !(script = view_script_open(vo.script, o->cmd))) goto out;
    if (!vo.size_given) o->rd.width = o->rd.height = 768;
    lc_device_desc dd = {.target = o->target_set ? o->target : LC_TARGET_AUTO, .threads = o->threads,
                         .log = o->quiet ? NULL : log_warning, .log_user = (void *)o->cmd};
    lc_device_desc ud = {.target = LC_TARGET_SCALAR, .threads = 1};
    if (lc_device_create(&dd, &dev) != LC_OK || lc_device_create(&ud, &ui_dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        goto out;
    }
    const cli_kind *kind = NULL;
    if ((rc = load(o, &vo, dev, v, &kind)) != 0) goto out;
    v->ui_dev = ui_dev;
    v->wake = view_gui_wake;
    v->ro = o, v->kind = kind, v->load_dev = dev;
    rc = CLI_EXIT_FAIL;
    if (view_render_start(v) == 0) {
        view_hist_start(v);
        view_frames_start(v);
        view_run run = {v, ui_dev, script, vo.screenshot};
        rc = view_gui_run(&run);
        view_frames_stop(v);
        view_hist_stop(v);
        view_render_stop(v);
        view_gui_close();
    }
    lc_volume_destroy(v->volume);
    lc_volume_destroy(v->next_volume);
    lc_volume_destroy(v->retired);
    lc_device_destroy(v->frames_dev);
    lc_tf_destroy(v->initial_tf);
    free(v->shown.rgba);
    free(v->refined);
    pthread_mutex_destroy(&v->mu);
    pthread_mutex_destroy(&v->vol_mu);
    pthread_cond_destroy(&v->cv);
out:
    view_script_close(script);
    lc_device_destroy(ui_dev);
    lc_device_destroy(dev);
    free(rargv);
    if (o) free(o->files);
    free(o);
    free(v);
    return rc;
}

int cli_view_available(void) { return 1; }
