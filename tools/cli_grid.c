/* lanecast render VOLUME: the structured-grid flags, defaults and stats
 * (Knoll et al. 2011). See cli_kind.h. */
#include <math.h>
#include <string.h>
#include "args.h"
#include "cli_kind.h"

static const char help[] =
    "volumes (structured grids, Knoll et al. 2011):\n"
    "  INPUT                 .nrrd/.nhdr (raw or gzip, either endianness), .mhd/.mha, or a raw file\n"
    "                        with --dims\n"
    "  INPUT...              a DICOM series (GDCM): a folder, its files (several INPUTs, e.g.\n"
    "                        series/*.dcm) or one file of it (the series of its folder); slices in\n"
    "                        order along the slice normal, rescaled (CT: Hounsfield units)\n"
    "  --series N|UID        DICOM: the series to read when the input holds several (N from 1, or\n"
    "                        its Series Instance UID; lanecast info INPUT lists them)\n"
    "  --dims X,Y,Z          raw volume sizes in nodes (makes INPUT a raw volume)\n"
    "  --type T              raw value type: uint8, uint16, int16 or float32\n"
    "  --big-endian          raw values are big-endian\n"
    "  --spacing sx,sy,sz    node spacing (default: the header's, else 1,1,1)\n"
    "  --brick L             BVH leaf bricks of L^3 voxels: 1, 2, 4, 8, 16 (default by size)\n"
    "  --preintegrated       classify with the pre-integrated TF table\n"
    "  --method bvh|brute    the implicit min-max BVH (default) or every sample without it\n"
    "  --no-bvh              the same as --method brute\n"
    "  --rda R               differential sampling: the step grows by R*dt per sample (default 0)\n"
    "  --delta-c C --delta-p P --delta-sv S   BVH heuristics (eqs. 5-7; defaults 1e-3, 1.5, 1e-4;\n"
    "                        a negative value turns one off)\n"
    "  defaults: method bvh, dt half the smallest spacing; TF from the histogram (lc_tf_auto): the\n"
    "  dominant value's hill is transparent background, the range runs from its edge to the 99th\n"
    "  percentile of the other values, opacity rises over it to 16 / the volume's diagonal, colour\n"
    "  map viridis (--colormap to change it); with --tf PRESET: the data's min..max and a peak\n"
    "  extinction of 8 / the diagonal\n"
    "  examples: lanecast render engine.nhdr -o engine.png --shade phong --stats\n"
    "            lanecast render HeadMRVolume.mhd --colormap inferno --orbit 36 -o head_%02d.png\n"
    "            lanecast render ct_folder/ --series 2 -o ct.png --shade phong\n"
    "\n";

/* Parameters the flags set; applied to the volume once it is loaded. */
static lc_grid_params params;
static int no_bvh;

static int parse_type(const char *cmd, const char *v, const char **name)
{
    static const char *const alias[][2] = {{"uint8", "uint8"}, {"u8", "uint8"},     {"uint16", "uint16"},
                                           {"u16", "uint16"},  {"int16", "int16"},  {"i16", "int16"},
                                           {"float32", "float32"}, {"float", "float32"}, {"f32", "float32"}};
    for (size_t k = 0; k < sizeof alias / sizeof alias[0]; k++)
        if (!strcmp(v, alias[k][0])) return *name = alias[k][1], 0;
    fprintf(stderr, "%s: --type: '%s' is not uint8, uint16, int16 or float32\n", cmd, v);
    return -1;
}

static int parse_flag(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first)
{
    const char *a = argv[*i], *v;
    static const char *const flags[] = {"--preintegrated", "--no-bvh", "--big-endian", "--dims",    "--type",
                                        "--spacing",       "--brick",  "--rda",        "--delta-c", "--delta-p",
                                        "--delta-sv",      "--series"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!*first) *first = a;
    if (!strcmp(a, "--preintegrated")) return params.preintegrated = 1, 1;
    if (!strcmp(a, "--no-bvh")) return no_bvh = 1, 1;
    if (!strcmp(a, "--big-endian")) return cli_load_add(load, cmd, "endian", "big") ? -1 : 1;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--series")) return cli_load_add(load, cmd, "series", v) ? -1 : 1;
    if (!strcmp(a, "--dims")) {
        long long d[3];
        if (arg_ints(cmd, a, v, 3, 2, 2147483647LL, d)) return -1;
        if ((double)d[0] * (double)d[1] * (double)d[2] > 2147483583.0) { /* the library's limit: 2^31 - 65 values */
            fprintf(stderr, "%s: --dims: %s is %.0f nodes, more than a grid holds (2^31 - 65)\n", cmd, v,
                    (double)d[0] * (double)d[1] * (double)d[2]);
            return -1;
        }
        load->format = "raw-volume";
        return cli_load_add(load, cmd, "size", v) ? -1 : 1;
    }
    if (!strcmp(a, "--type")) {
        const char *t;
        return parse_type(cmd, v, &t) || cli_load_add(load, cmd, "type", t) ? -1 : 1;
    }
    if (!strcmp(a, "--spacing")) {
        lc_vec3 s;
        if (arg_vec3(cmd, a, v, &s)) return -1;
        if (!(s.x > 0 && s.y > 0 && s.z > 0)) {
            fprintf(stderr, "%s: --spacing: '%s': each spacing must be > 0\n", cmd, v);
            return -1;
        }
        return cli_load_add(load, cmd, "spacing", v) ? -1 : 1;
    }
    if (!strcmp(a, "--brick")) {
        int b;
        if (arg_int(cmd, a, v, 1, 16, &b)) return -1;
        if (b & (b - 1)) {
            fprintf(stderr, "%s: --brick: %d is not 1, 2, 4, 8 or 16\n", cmd, b);
            return -1;
        }
        return cli_load_add(load, cmd, "brick", v) ? -1 : 1;
    }
    if (!strcmp(a, "--rda")) return arg_float(cmd, a, v, 0.0f, 1.0f, &params.rda) ? -1 : 1;
    float *d = !strcmp(a, "--delta-c") ? &params.delta_c : !strcmp(a, "--delta-p") ? &params.delta_p : &params.delta_sv;
    if (arg_float(cmd, a, v, -1e30f, 1e30f, d)) return -1;
    if (*d == 0.0f) *d = -1.0f; /* 0 would mean "default" in the API; here it means off */
    return 1;
}

static lc_status apply(lc_volume *v, lc_render_desc *rd)
{
    if (no_bvh) rd->method = LC_METHOD_BRUTE;
    return lc_grid_set_params(v, &params);
}

static lc_status default_tf(lc_device *dev, const lc_volume *v, const cli_tf_req *req, lc_tf **out)
{
    if (!req->preset) return lc_tf_auto(dev, v, req->colormap, req->tau, out); /* from the histogram */
    lc_grid_info gi;
    lc_status s = lc_grid_get_info(v, &gi);
    if (s != LC_OK) return s;
    /* a preset: peak extinction so the densest material stops a ray in about 1/8 of the diagonal */
    float dx = gi.bounds.hi.x - gi.bounds.lo.x, dy = gi.bounds.hi.y - gi.bounds.lo.y, dz = gi.bounds.hi.z - gi.bounds.lo.z;
    /* the diagonal in double: squares of tiny (1e-30) or huge extents leave
       float's range; the loaders keep spacings in [1e-30, 1e30]
       (lci_vol_geometry), so 8 / diag is finite */
    double diag = sqrt((double)dx * dx + (double)dy * dy + (double)dz * dz);
    float t = req->tau > 0.0f ? req->tau : (float)(8.0 / diag);
    return lc_tf_preset(dev, req->preset, 1, t, out);
}

static void print_stats(const lc_volume *v, double load_seconds, FILE *f)
{
    static const char *types[] = {"?", "uint8", "uint16", "int16", "float32"};
    lc_grid_info in;
    if (lc_grid_get_info(v, &in) != LC_OK) return;
    fprintf(f, "volume        %dx%dx%d %s, spacing %g,%g,%g, values %g..%g\n", in.size[0], in.size[1], in.size[2],
            types[in.type >= 1 && in.type <= 4 ? in.type : 0], (double)in.spacing.x, (double)in.spacing.y,
            (double)in.spacing.z, (double)in.value_min, (double)in.value_max);
    char copy[64];
    snprintf(copy, sizeof copy, "sampling copy, %d bytes a voxel,", in.copy_voxel_bytes);
    fprintf(f, "layout        %s %.2f MB voxels + %.2f MB overhead (%.1f%%)\n",
            in.copy_voxel_bytes ? copy : in.layout == LC_LAYOUT_BRICKED ? "4^3 bricks," : "linear,",
            (double)in.data_bytes / 1e6,
            (double)in.layout_overhead_bytes / 1e6, 100.0 * (double)in.layout_overhead_bytes / (double)in.data_bytes);
    fprintf(f, "bvh           L=%d, %llu nodes (%llu leaves), depth %d, %.2f MB, build %.3f s\n", in.brick,
            (unsigned long long)in.bvh_nodes, (unsigned long long)in.bvh_leaves, in.bvh_depth,
            (double)in.bvh_bytes / 1e6, in.bvh_build_seconds);
    fprintf(f, "load          %.3f s (reading, bricking and BVH build)\n", load_seconds);
}

const cli_kind cli_grid = {LC_KIND_GRID, help, parse_flag, apply, NULL, default_tf, print_stats, "voxel samples"};
