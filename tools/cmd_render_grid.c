/* lanecast render VOLUME: the volume flags and loading (see cmd_render_grid.h). */
#include "cmd_render_grid.h"
#include <string.h>
#include <strings.h>
#include "args.h"

const char grid_render_help[] =
    "volumes (structured grids, Knoll et al. 2011):\n"
    "  INPUT                 .nrrd/.nhdr (raw or gzip, either endianness), .mhd/.mha, or a raw file\n"
    "                        with --dims\n"
    "  --dims X,Y,Z          raw volume sizes in nodes (makes INPUT a raw volume)\n"
    "  --type T              raw value type: uint8, uint16, int16 or float32\n"
    "  --big-endian          raw values are big-endian\n"
    "  --spacing sx,sy,sz    node spacing (default: the header's, else 1,1,1)\n"
    "  --brick L             BVH leaf bricks of L^3 voxels: 1, 2, 4, 8, 16 (default by size)\n"
    "  --preintegrated       classify with the pre-integrated TF table\n"
    "  --no-bvh              brute force: every sample, no BVH (same as --method brute)\n"
    "  --rda R               differential sampling: the step grows by R*dt per sample (default 0)\n"
    "  --delta-c C --delta-p P --delta-sv S   BVH heuristics (eqs. 5-7; defaults 1e-3, 1.5, 1e-4;\n"
    "                        a negative value turns one off)\n"
    "  (--method bvh|brute; default dt is half the smallest spacing, range the data's min..max)\n"
    "\n";

int grid_is_volume(const grid_opts *g, const char *input)
{
    if (!input) return 0;
    if (g->dims_given) return 1;
    const char *dot = strrchr(input, '.'), *slash = strrchr(input, '/');
    if (!dot || (slash && dot < slash)) return 0;
    dot++;
    return !strcasecmp(dot, "nrrd") || !strcasecmp(dot, "nhdr") || !strcasecmp(dot, "mhd") || !strcasecmp(dot, "mha");
}

static int parse_type(const char *cmd, const char *v, lc_value_type *t)
{
    if (!strcmp(v, "uint8") || !strcmp(v, "u8")) *t = LC_VALUE_UINT8;
    else if (!strcmp(v, "uint16") || !strcmp(v, "u16")) *t = LC_VALUE_UINT16;
    else if (!strcmp(v, "int16") || !strcmp(v, "i16")) *t = LC_VALUE_INT16;
    else if (!strcmp(v, "float32") || !strcmp(v, "float") || !strcmp(v, "f32")) *t = LC_VALUE_FLOAT32;
    else {
        fprintf(stderr, "%s: --type: '%s' is not uint8, uint16, int16 or float32\n", cmd, v);
        return -1;
    }
    return 0;
}

int grid_parse_flag(grid_opts *g, const char *cmd, int argc, char **argv, int *i)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--preintegrated")) {
        g->preintegrated = 1;
        return 1;
    }
    if (!strcmp(a, "--no-bvh")) {
        g->no_bvh = 1;
        return 1;
    }
    if (!strcmp(a, "--big-endian")) {
        g->load.big_endian = 1;
        return 1;
    }
    if (strcmp(a, "--dims") && strcmp(a, "--type") && strcmp(a, "--spacing") && strcmp(a, "--brick") &&
        strcmp(a, "--rda") && strcmp(a, "--delta-c") && strcmp(a, "--delta-p") && strcmp(a, "--delta-sv"))
        return 0;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--dims")) {
        lc_vec3 d;
        if (arg_vec3(cmd, a, v, &d)) return -1;
        float dd[3] = {d.x, d.y, d.z};
        for (int k = 0; k < 3; k++) {
            if (!(dd[k] >= 2 && dd[k] <= 2147483647.0f && dd[k] == (float)(long)dd[k])) {
                fprintf(stderr, "%s: --dims: '%s': expected three integers >= 2\n", cmd, v);
                return -1;
            }
            g->load.size[k] = (int)dd[k];
        }
        g->dims_given = 1;
        return 1;
    }
    if (!strcmp(a, "--type")) return parse_type(cmd, v, &g->load.type) ? -1 : 1;
    if (!strcmp(a, "--spacing")) {
        if (arg_vec3(cmd, a, v, &g->load.spacing)) return -1;
        if (!(g->load.spacing.x > 0 && g->load.spacing.y > 0 && g->load.spacing.z > 0)) {
            fprintf(stderr, "%s: --spacing: '%s': each spacing must be > 0\n", cmd, v);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--brick")) {
        if (arg_int(cmd, a, v, 1, 16, &g->load.brick)) return -1;
        if (g->load.brick & (g->load.brick - 1)) {
            fprintf(stderr, "%s: --brick: %d is not 1, 2, 4, 8 or 16\n", cmd, g->load.brick);
            return -1;
        }
        return 1;
    }
    if (!strcmp(a, "--rda")) return arg_float(cmd, a, v, 0.0f, 1.0f, &g->rda) ? -1 : 1;
    float *d = !strcmp(a, "--delta-c") ? &g->delta_c : !strcmp(a, "--delta-p") ? &g->delta_p : &g->delta_sv;
    if (arg_float(cmd, a, v, -1e30f, 1e30f, d)) return -1;
    if (*d == 0.0f) *d = -1.0f; /* 0 would mean "default" in the API; here it means off */
    return 1;
}

void grid_apply(const grid_opts *g, lc_render_desc *rd)
{
    if (g->no_bvh) rd->method = LC_METHOD_BRUTE;
    rd->grid_params.preintegrated = g->preintegrated;
    rd->grid_params.rda = g->rda;
    rd->grid_params.delta_c = g->delta_c;
    rd->grid_params.delta_p = g->delta_p;
    rd->grid_params.delta_sv = g->delta_sv;
}

lc_status grid_load(lc_device *dev, const grid_opts *g, const char *input, lc_grid **out, lc_grid_info *info)
{
    lc_status s = lc_grid_load(dev, input, &g->load, out);
    if (s == LC_OK) lc_grid_get_info(*out, info);
    return s;
}

void grid_print_stats(const lc_grid_info *in, FILE *f)
{
    static const char *types[] = {"?", "uint8", "uint16", "int16", "float32"};
    fprintf(f, "volume        %dx%dx%d %s, spacing %g,%g,%g, values %g..%g\n", in->size[0], in->size[1], in->size[2],
            types[in->type >= 1 && in->type <= 4 ? in->type : 0], (double)in->spacing.x, (double)in->spacing.y,
            (double)in->spacing.z, (double)in->value_min, (double)in->value_max);
    fprintf(f, "layout        %s, %.2f MB voxels + %.2f MB overhead (%.1f%%)\n",
            in->layout == LC_LAYOUT_BRICKED ? "4^3 bricks" : "linear", (double)in->data_bytes / 1e6,
            (double)in->layout_overhead_bytes / 1e6, 100.0 * (double)in->layout_overhead_bytes / (double)in->data_bytes);
    fprintf(f, "bvh           L=%d, %llu nodes (%llu leaves), depth %d, %.2f MB, build %.3f s\n", in->brick,
            (unsigned long long)in->bvh_nodes, (unsigned long long)in->bvh_leaves, in->bvh_depth,
            (double)in->bvh_bytes / 1e6, in->bvh_build_seconds);
}
