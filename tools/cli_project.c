/* lanecast render --mode project: column maps of particle data
 * (lc_particles_project), written as float maps (lc_map_write: .npy with a
 * JSON sidecar, .fits, .exr) or as colour images of them (lc_map_colorize,
 * log scale by default). Its flags are parsed here and refused in the other
 * modes; cmd_render.c hands the run over once it knows the input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "args.h"
#include "cli.h"
#include "progress.h"
#include "render_opts.h"

const char cli_project_help[] =
    "projections (--mode project; particle data):\n"
    "  The column of each pixel: sum_i kappa k_i W_i integrated along the line of sight, with the\n"
    "  particles' kernel (--kernel; SPH kernels with support H = the particle radius, e.g. GADGET's\n"
    "  HSML), k_i the --value (GADGET and HDF5 default to a column-density map: mass, or with an\n"
    "  SPH kernel rho, whose SPH interpolant sum m / rho rho W integrates to sum m W).\n"
    "  Exact pixel averages by default: every particle puts exactly its amount into the pixels it\n"
    "  covers, at any size from 0.01 to 100 pixels and beyond (no smoothing-length floor).\n"
    "  Orthographic views only (default: down -z framing the particles' x, y extent; --view\n"
    "  AZ,EL or --eye/--at with --ortho HEIGHT for others).\n"
    "  --sample exact|centre  pixel averages (default) or the column at pixel centres (SPLASH's and\n"
    "                        yt's convention, without their smoothing-length floor)\n"
    "  --weight FIELD        a weighted projection sum w A W / sum w W per pixel: A the --value,\n"
    "                        w the file's FIELD (as --value names it) times the volume element:\n"
    "                        for SPH data --weight mass is the density-weighted mean of A\n"
    "  --depth D             only the slab of thickness D (world units) centred on the view's\n"
    "                        --at (default the data's centre) across the line of sight; particles\n"
    "                        cut by a face keep their kernel's exact mass inside the slab\n"
    "  --log | --linear      colour images: log10 scale (the default) or linear\n"
    "  --range LO,HI         colour images: the data values mapped to the colour map's ends\n"
    "                        (default: log from the 0.5th percentile of the positive pixels to\n"
    "                        the largest; linear from min to max)\n"
    "  --colorbar            colour images: a colour bar at the right (the range is printed)\n"
    "  --colormap NAME, --tf PRESET|FILE   the colours (default viridis)\n"
    "  -o map.npy|.fits|.exr writes the float map itself: .npy (with map.npy.json: quantity, units,\n"
    "                        kernel, extent, axes), .fits (cfitsio: BUNIT, BTYPE, KERNEL, WCS,\n"
    "                        XMIN..YMAX), .exr (one float channel); any other extension a colour image\n"
    "  examples: lanecast render snap.hdf5 --mode project --kernel wendland-c2 -o sigma.fits\n"
    "            lanecast render snap.dat --types 0 --mode project --kernel m4 --size 2048x2048 \\\n"
    "                    -o sigma.png --colorbar --colormap inferno\n"
    "            lanecast render snap.dat --types 0 --mode project --value u --weight mass -o u.npy\n"
    "            lanecast render snap.dat --mode project --kernel m4 --depth 5 --view 0,0 -o slab.png\n"
    "\n";

/* 1 consumed, 0 not one, -1 bad value. */
int cli_project_flag(ropts *o, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--log") || !strcmp(a, "--linear") || !strcmp(a, "--colorbar")) {
        if (!o->pj.first) o->pj.first = a;
        if (!strcmp(a, "--colorbar")) o->pj.colorbar = 1;
        else o->pj.linear = !strcmp(a, "--linear");
        return 1;
    }
    if (strcmp(a, "--sample") && strcmp(a, "--weight") && strcmp(a, "--depth")) return 0;
    if (!o->pj.first) o->pj.first = a;
    if (!(v = arg_value(o->cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--weight")) return o->pj.weight = v, 1;
    if (!strcmp(a, "--depth")) return arg_float(o->cmd, a, v, 1e-30f, 1e30f, &o->pj.depth) ? -1 : 1;
    if (!strcmp(v, "exact")) o->pj.sample = LC_PROJECT_EXACT;
    else if (!strcmp(v, "centre") || !strcmp(v, "center")) o->pj.sample = LC_PROJECT_CENTRE;
    else {
        fprintf(stderr, "%s: --sample: '%s' is not exact or centre\n", o->cmd, v);
        return -1;
    }
    return 1;
}

int cli_project_check(const ropts *o)
{
    if (!o->pj.on && o->pj.first) {
        fprintf(stderr, "%s: %s applies to --mode project only\n", o->cmd, o->pj.first);
        return -1;
    }
    if (o->pj.on && (o->orbit || o->seq)) {
        fprintf(stderr, "%s: --mode project: %s is not supported (one map per run)\n", o->cmd,
                o->orbit ? "--orbit" : "--frames");
        return -1;
    }
    return 0;
}

/* The input with the particle flags applied; value: another --value (the
 * --weight FIELD), or NULL. */
static lc_status load_set(ropts *o, lc_device *dev, const cli_kind *kind, const char *value, lc_volume **out)
{
    cli_load l = o->load; /* a copy: the option pointers must point into it */
    for (int i = 0; i < l.n; i++) l.opt[i].value = l.val[i];
    if (value && cli_load_add(&l, o->cmd, "value", value)) return LC_ERROR_INVALID_ARGUMENT;
    /* a projection reads the particles only: no BVH (most of a large set's load) */
    if (cli_load_add(&l, o->cmd, "defer_bvh", "1")) return LC_ERROR_INVALID_ARGUMENT;
    lc_load_desc ld = {.format = l.format, .companion = o->topology, .frame = o->frame, .options = l.opt, .noptions = l.n};
    lc_status s = lc_volume_load(dev, o->input, &ld, out);
    if (s != LC_OK) return s;
    return kind->apply(*out, &o->rd);
}

static const char *value_name(const ropts *o)
{
    for (int i = 0; i < o->load.n; i++)
        if (!strcmp(o->load.opt[i].key, "value")) return o->load.val[i];
    return NULL;
}

/* An SPH kernel asked of the loaders (load option kernel): their weights are then
 * m / rho A (the SPH interpolant of A). */
static int sph_weights(const ropts *o)
{
    for (int i = 0; i < o->load.n; i++)
        if (!strcmp(o->load.opt[i].key, "kernel")) return strcmp(o->load.val[i], "gaussian") != 0;
    return 0;
}

static lc_tf *colours(ropts *o, lc_device *dev)
{
    lc_tf *tf = NULL;
    const char *name = o->colormap ? o->colormap : o->tf;
    if (!name) return NULL;
    int preset = 0;
    for (int i = 0; lc_tf_preset_name(i); i++) preset |= !strcmp(name, lc_tf_preset_name(i));
    lc_status s = preset ? lc_tf_preset(dev, name, 1, 1.0f, &tf) : lc_tf_load(dev, name, &tf);
    if (s != LC_OK) fprintf(stderr, "%s: --tf: %s\n", o->cmd, lc_last_error());
    return s == LC_OK ? tf : (lc_tf *)-1;
}

static void print_stats(const lc_project_info *pi, double load_s, const lc_volume *vol)
{
    lc_particles_info inf;
    if (lc_particles_get_info(vol, &inf) == LC_OK)
        printf("particles     %zu (%zu dropped), radius %.4g..%.4g, kernel %s\n", inf.count, inf.dropped,
               (double)inf.min_radius, (double)inf.max_radius, lc_kernel_name(inf.params.kernel));
    printf("load          %.3f s (reading; a projection builds no BVH)\n", load_s);
    printf("project       %.3f s, %d threads, %llu particles in the image, column table rank %d\n", pi->seconds,
           pi->threads, (unsigned long long)pi->particles, pi->rank);
    printf("kernel-pixels %llu (%.1f M/s)\n", (unsigned long long)pi->evaluations,
           (double)pi->evaluations / pi->seconds / 1e6);
    printf("map sum       %.9g (sum of pixels x pixel area)\n", pi->mass);
    printf("extent        %.6g..%.6g x %.6g..%.6g (pixel %.6g)\n", pi->extent[0], pi->extent[1], pi->extent[2],
           pi->extent[3], pi->pixel);
}

/* Writes the map (float formats) or its colour image. */
static lc_status write_out(ropts *o, lc_device *dev, const float *map, const lc_project_info *pi, const char *kname)
{
    const char *val = value_name(o);
    char quantity[256], units[256];
    if (o->pj.weight)
        snprintf(quantity, sizeof quantity, "%s weighted by %s along the line of sight", val ? val : "value", o->pj.weight);
    else
        snprintf(quantity, sizeof quantity, "column of %s%s", val ? val : "value",
                 val && (!strcmp(val, "mass") || (!strcmp(val, "rho") && sph_weights(o))) ? " (surface density)" : "");
    int sigma = !o->pj.weight && val && !strcmp(val, "rho") && sph_weights(o); /* rho times a length */
    snprintf(units, sizeof units, o->pj.weight ? "the file's units of %s" : "the file's units of %s per length^2",
             sigma ? "mass" : val ? val : "value");
    int W = o->rd.width, H = o->rd.height;
    if (lc_map_format(o->output)) {
        lc_map_desc md = {W, H, map, quantity, units, kname, o->pj.sample == LC_PROJECT_CENTRE ? "centre" : "exact",
                          o->pj.depth, pi};
        return lc_map_write(dev, o->output, &md);
    }
    lc_tf *tf = colours(o, dev);
    if (tf == (lc_tf *)-1) return LC_ERROR_INVALID_ARGUMENT;
    int cw = o->pj.colorbar ? lc_map_colorbar_width(W) : 0;
    float *rgba = malloc(sizeof(float) * 4 * (size_t)(W + cw) * (size_t)H), used[2];
    lc_status s = rgba ? LC_OK : LC_ERROR_OUT_OF_MEMORY;
    lc_map_color_desc cd = {W, H, map, tf, {o->rd.range[0], o->rd.range[1]}, o->pj.linear, o->pj.colorbar};
    if (s == LC_OK) s = lc_map_colorize(dev, &cd, rgba, used);
    lc_image_desc id = {W + cw, H, rgba, {0, 0, 0}, 0};
    if (s == LC_OK) s = lc_image_write(dev, o->output, &id);
    if (s == LC_OK && !o->quiet)
        printf("colours       %s %.6g .. %.6g%s\n", o->pj.linear ? "linear" : "log10", (double)used[0], (double)used[1],
               o->pj.colorbar ? " (colour bar bottom to top)" : "");
    free(rgba);
    lc_tf_destroy(tf);
    return s;
}

/* GADGET and HDF5 snapshots project their surface density unless --value says
 * otherwise: their masses, or with an SPH kernel the interpolant of rho
 * (sum_j m_j / rho_j rho_j W_j = sum_j m_j W_j; --value mass would be
 * sum_j m_j^2 / rho_j W_j). */
static int default_value(ropts *o, lc_device *dev)
{
    lc_file_info fi;
    lc_load_desc ld = {.format = o->load.format, .options = o->load.opt, .noptions = o->load.n};
    if (value_name(o) || lc_file_probe(dev, o->input, &ld, &fi) != LC_OK) return 0;
    if (strcmp(fi.format, "gadget") && strcmp(fi.format, "hdf5")) return 0;
    return cli_load_add(&o->load, o->cmd, "value", sph_weights(o) ? "rho" : "mass");
}

int cli_project_run(ropts *o, lc_device *dev, const cli_kind *kind)
{
    if (kind->kind != LC_KIND_PARTICLES) {
        fprintf(stderr, "%s: --mode project needs particle data; %s holds %s\n", o->cmd, o->input,
                lc_kind_name(kind->kind));
        return CLI_EXIT_USAGE;
    }
    for (int k = 0; k < o->load.n; k++)
        if (!strcmp(o->load.opt[k].key, "normalise")) { /* the maps do not read the normalising weights */
            fprintf(stderr, "%s: --normalise applies to the dvr, mip, iso and slice modes; a projection's normalised "
                    "form is --weight FIELD (sum w A W / sum w W)\n", o->cmd);
            return CLI_EXIT_USAGE;
        }
    if (!lc_map_format(o->output) && lc_image_check(NULL, o->output) != LC_OK) {
        fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
        return CLI_EXIT_FAIL;
    }
    if (default_value(o, dev)) return CLI_EXIT_FAIL;
    double t0 = now_seconds();
    lc_volume *vol = NULL, *wv = NULL;
    lc_status s = load_set(o, dev, kind, NULL, &vol);
    if (s == LC_OK && o->pj.weight) s = load_set(o, dev, kind, o->pj.weight, &wv);
    double load_s = now_seconds() - t0;
    float *map = NULL;
    lc_project_info pi;
    if (s == LC_OK && !(map = malloc(sizeof(float) * (size_t)o->rd.width * (size_t)o->rd.height))) {
        fprintf(stderr, "%s: out of memory for a %dx%d map\n", o->cmd, o->rd.width, o->rd.height);
        s = LC_ERROR_OUT_OF_MEMORY;
    }
    lc_project_desc pd = {.width = o->rd.width, .height = o->rd.height, .sample = o->pj.sample, .weight = wv,
                          .depth = o->pj.depth};
    if (s == LC_OK && (o->camera_set || o->view_set)) {
        s = render_view_camera(o, vol, 0, &pd.camera);
        if (!o->camera_set) pd.camera.projection = LC_ORTHOGRAPHIC; /* --view: framed orthographically */
    }
    int said = 0;
    if (s == LC_OK) {
        s = lc_particles_project(dev, vol, &pd, map, &pi);
        if (s == LC_ERROR_UNSUPPORTED && pd.camera.projection == LC_PERSPECTIVE)
            said = fprintf(stderr, "%s: --mode project: projections are orthographic: give --ortho HEIGHT with "
                           "--eye/--at\n", o->cmd);
    }
    lc_particles_info inf;
    const char *kname = s == LC_OK && lc_particles_get_info(vol, &inf) == LC_OK ? lc_kernel_name(inf.params.kernel) : NULL;
    if (s == LC_OK) s = write_out(o, dev, map, &pi, kname);
    if (s == LC_OK && !o->quiet) printf("wrote %s (%dx%d map)\n", o->output, o->rd.width, o->rd.height);
    if (s == LC_OK && o->stats) print_stats(&pi, load_s, vol);
    if (s != LC_OK && !said) fprintf(stderr, "%s: %s\n", o->cmd, lc_last_error());
    free(map);
    lc_volume_destroy(wv);
    lc_volume_destroy(vol);
    return s == LC_OK ? 0 : CLI_EXIT_FAIL;
}
