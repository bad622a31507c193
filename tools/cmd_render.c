/* lanecast render / lanecast demo: load (or generate) data, render, write.
 * Kind-neutral: the kinds' flags, defaults and stats come from their rows
 * (cli_kind.h); the kind is decided once, from the input file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "cli_mpi.h"
#include "args.h"
#include "cli.h"
#include "cli_kind.h"
#include "progress.h"
#include "render_opts.h"


/* The kind of the input, decided once through the formats registry; flags of
 * another kind are an error (they would be ignored). Returns the row or NULL
 * (message printed; *usage set when the flags were at fault). *fopts: the
 * option keys of the file's format ("" for the demo). */
const cli_kind *render_decide_kind(ropts *o, lc_device *dev, lc_kind forced, int *usage, int64_t *frames,
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
        if (cli_kinds[k]->kind == kind) row = cli_kinds[k];
    for (int k = 0; k < NKINDS && row; k++)
        if (cli_kinds[k] != row && o->first_flag[k]) {
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

/* --resample N: the particles' grid, its values and its TF while a frame renders through it. */
typedef struct resampled {
    lc_volume *grid;
    float *values;
    lc_tf *tf; /* field 0 of the particles' TF when they have several fields (the grid holds their sum) */
    lc_resample_info info;
    int nfields;
} resampled;

static int reported; /* the error was printed where it happened */

/* Deposits the particles of vol on an N^3 grid over their bounds and makes
 * it a grid volume borrowing the values; the desc's range becomes the
 * particles' default range when neither the flags nor the TF give one (the
 * grid's own would be its voxel range), its method the grid's default. */
static lc_status resample_grid(ropts *o, lc_device *dev, const lc_volume *vol, const lc_tf *tf, resampled *r)
{
    lc_volume_info vi;
    lc_status s = lc_volume_get_info(vol, &vi);
    if (s != LC_OK) return s;
    if (vi.kind != LC_KIND_PARTICLES) {
        fprintf(stderr, "%s: --resample applies to particle data; %s holds %s data\n", o->cmd, o->input,
                lc_kind_name(vi.kind));
        return reported = 1, LC_ERROR_INVALID_ARGUMENT;
    }
    lc_resample_desc d = {.size = {o->resample, o->resample, o->resample}, .field = -1, .max_memory = o->max_memory};
    if (cli_resample_values(o->cmd, dev, vol, &d, o->progress, &r->values, &r->info) != LC_OK)
        return reported = 1, LC_ERROR_INVALID_ARGUMENT;
    lc_grid_desc gd = {.size = {o->resample, o->resample, o->resample}, .type = LC_VALUE_FLOAT32, .data = r->values,
                       .spacing = r->info.spacing, .origin = r->info.origin, .borrow = 1, .layout = LC_LAYOUT_LINEAR};
    if ((s = lc_grid_create(dev, &gd, &r->grid)) != LC_OK) return s;
    r->nfields = vi.nfields;
    lc_tf_field f0 = {0};
    if (tf && (s = lc_tf_get_field(tf, 0, &f0)) != LC_OK) return s;
    if (tf && lc_tf_field_count(tf) > 1 && (s = lc_tf_create(dev, &f0, 1, &r->tf)) != LC_OK) return s;
    if (o->rd.range[0] == 0.0f && o->rd.range[1] == 0.0f && !f0.has_range)
        o->rd.range[0] = vi.range[0], o->rd.range[1] = vi.range[1];
    o->rd.method = LC_METHOD_DEFAULT;
    return LC_OK;
}

static void resampled_free(resampled *r)
{
    lc_volume_destroy(r->grid);
    lc_tf_destroy(r->tf);
    free(r->values);
    memset(r, 0, sizeof *r);
}

static void print_stats(const ropts *o, const cli_kind *kind, const lc_volume *vol, double load_s,
                        const lc_render_stats *st, const resampled *rs)
{
    double t = st->seconds;
    printf("target        %s (%d lanes), %d threads\n", lc_target_name(st->target), lc_target_lanes(st->target),
           st->threads);
    kind->print_stats(vol, load_s, stdout);
    if (rs->grid) {
        printf("resample      %d^3 grid (float32) over the bounds, spacing %g %g %g%s: deposit %.3f s, %.1f MiB, "
               "%llu terms; the image is the grid renderer's\n",
               o->resample, (double)rs->info.spacing.x, (double)rs->info.spacing.y, (double)rs->info.spacing.z,
               rs->nfields > 1 ? ", the sum of every field" : "", rs->info.seconds,
               (double)rs->info.bytes / 1048576.0, (unsigned long long)rs->info.evaluations);
        kind = cli_kind_of(LC_KIND_GRID);
    }
    printf("render        %.3f s (%.2f fps)\n", t, 1.0 / t);
    printf("rays          %llu\n", (unsigned long long)st->rays);
    printf("samples       %llu\n", (unsigned long long)st->samples);
    printf("%s %llu (%.1f M/s)\n", kind->evals, (unsigned long long)st->kernel_evals, (double)st->kernel_evals / t / 1e6);
    printf("nodes         %llu, leaves %llu, passes %llu\n", (unsigned long long)st->nodes,
           (unsigned long long)st->leaves, (unsigned long long)st->passes);
    (void)o;
}

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
lc_status render_load(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t frame, lc_volume **vol,
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
        s = cli_mpi_ranks() > 1 ? cli_mpi_load(dev, o->input, &ld, o->rd.dt, vol) : lc_volume_load(dev, o->input, &ld, vol);
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
lc_vec3 render_rotate(lc_vec3 v, lc_vec3 k, float a)
{
    float c = cosf(a), s = sinf(a), d = (k.x * v.x + k.y * v.y + k.z * v.z) * (1.0f - c);
    lc_vec3 x = {k.y * v.z - k.z * v.y, k.z * v.x - k.x * v.z, k.x * v.y - k.y * v.x};
    return (lc_vec3){v.x * c + x.x * s + k.x * d, v.y * c + x.y * s + k.y * d, v.z * c + x.z * s + k.z * d};
}

/* The camera of orbit image i (of o->orbit; i = 0 without --orbit). */
lc_status render_view_camera(const ropts *o, const lc_volume *vol, int i, lc_camera *cam)
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
    d = render_rotate(d, up, step * 3.14159265f / 180.0f);
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
    lc_status s = render_load(o, dev, demo, kind, f, &vol, tf);
    s = cli_mpi_agree(dev, s); /* a rank that could not load stops every rank */
    double load_s = seconds_since(&ts0);
    resampled rs = {0};
    lc_method method = o->rd.method;
    float range[2] = {o->rd.range[0], o->rd.range[1]};
    if (s == LC_OK && o->resample) s = resample_grid(o, dev, vol, *tf, &rs);
    lc_camera given = o->rd.camera;
    int views = o->orbit ? o->orbit : 1;
    char name[4096];
    for (int v = 0; s == LC_OK && v < views; v++) {
        if (o->orbit) render_frame_name(o->output, v, name, sizeof name);
        else snprintf(name, sizeof name, "%s", out);
        s = render_view_camera(o, vol, v, &o->rd.camera);
        char label[64];
        if (count > 1 || views > 1)
            snprintf(label, sizeof label, "rendering %d/%d", (o->orbit ? v : index) + 1, o->orbit ? views : count);
        else
            snprintf(label, sizeof label, "rendering");
        progress_state ps = {label, now_seconds(), 0};
        o->rd.progress = o->progress ? render_progress : NULL;
        o->rd.progress_user = &ps;
        o->rd.volume = rs.grid ? rs.grid : vol;
        o->rd.tf = rs.tf ? rs.tf : *tf;
        lc_render_stats st;
        if (s == LC_OK) s = cli_mpi_ranks() > 1 ? cli_mpi_render(dev, &o->rd, o->composite, o->bands, rgba, o->stats, &st) : lc_render(dev, &o->rd, rgba, &st);
        progress_clear(&ps);
        o->rd.camera = given;
        lc_image_desc id = {o->rd.width, o->rd.height, rgba, o->background, o->alpha};
        int root = cli_mpi_rank() == 0; /* under mpirun rank 0 holds the image */
        lc_status rendered = s;          /* the same on every rank (lc_mpi_render agrees) */
        if (s == LC_OK && root) s = lc_image_write(dev, name, &id);
        if (cli_mpi_ranks() > 1 && rendered == LC_OK) s = cli_mpi_agree(dev, s);
        if (s == LC_OK && root && !o->quiet) printf("wrote %s (%dx%d)\n", name, o->rd.width, o->rd.height);
        if (s == LC_OK && root && o->stats) print_stats(o, kind, vol, load_s, &st, &rs);
        if (s != LC_OK && o->orbit)
            fprintf(stderr, "%s: orbit image %d (%s): %s; the orbit stops here\n", o->cmd, v, name, lc_last_error());
    }
    o->rd.volume = NULL;
    o->rd.method = method, o->rd.range[0] = range[0], o->rd.range[1] = range[1];
    resampled_free(&rs);
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
    if (o->seq) render_frame_name(o->output, o->first, out, sizeof out);
    if (o->orbit) render_frame_name(o->output, 0, out, sizeof out);
    /* fail on an unwritable output before any long work (float maps: when written) */
    if (!(o->pj.on && lc_map_format(out)) && lc_image_check(NULL, out) != LC_OK) {
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
    const cli_kind *kind = render_decide_kind(o, dev, demo ? LC_KIND_PARTICLES : LC_KIND_NONE, &usage, &frames, &fopts);
    if (kind && !demo && kind->defaults &&
        kind->defaults(o->cmd, &o->load, fopts, o->tf || o->colormap || o->nopacity))
        kind = NULL;
    if (cli_mpi_ranks() > 1) { /* a rank that cannot read the input stops every rank */
        lc_status ks = cli_mpi_agree(dev, kind ? LC_OK : usage ? LC_ERROR_INVALID_ARGUMENT : LC_ERROR_IO);
        if (ks != LC_OK && kind) fprintf(stderr, "%s: %s\n", o->cmd, lc_device_last_error(dev));
        if (ks != LC_OK) kind = NULL;
    }
    if (!kind) {
        lc_device_destroy(dev);
        return usage ? CLI_EXIT_USAGE : CLI_EXIT_FAIL;
    }
    if (o->resample && cli_mpi_ranks() > 1) {
        fprintf(stderr, "%s: --resample is not available under MPI (each rank would deposit every particle)\n", o->cmd);
        lc_device_destroy(dev);
        return CLI_EXIT_USAGE;
    }
    if (o->pj.on) { /* column maps: their own run (cli_project.c) */
        rc = cli_project_run(o, dev, kind);
        lc_device_destroy(dev);
        return rc;
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
        if (o->seq) render_frame_name(o->output, f, out, sizeof out);
        if (render_one(o, dev, demo, kind, f, out, &tf, rgba, index, count) != LC_OK) {
            if (o->seq)
                fprintf(stderr, "%s: frame %lld (%s): %s; the sequence stops here\n", o->cmd, (long long)f, out,
                        lc_last_error());
            else if (!o->orbit && !reported)
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
    int p = render_parse(&o, argc, argv, 1);
    if (p) return free(o.files), p > 0 ? 0 : CLI_EXIT_USAGE;
    int rc = cli_mpi_begin(o.cmd);
    rc = rc ? rc : cli_mpi_end(run(&o, 0));
    free(o.files);
    return rc;
}

int cli_demo(int argc, char **argv)
{
    ropts o;
    memset(&o, 0, sizeof o);
    o.cmd = "lanecast demo";
    o.output = "lanecast-demo.png";
    int p = render_parse(&o, argc, argv, 0);
    if (p) return p > 0 ? 0 : CLI_EXIT_USAGE;
    return run(&o, 1);
}
