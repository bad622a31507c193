/* lanecast render SET.rbf: the RBF set flags, defaults and stats (Jang et
 * al. 2004). See cli_kind.h. */
#include <string.h>
#include "args.h"
#include "cli_kind.h"

static const char help[] =
    "RBF sets (sums of truncated Gaussians plus a bias, Jang et al. 2004):\n"
    "  INPUT                 .rbf, text ('lanecast-rbf 1', 'bias B', 'count N', N lines 'x y z s w')\n"
    "                        or binary (docs/FORMATS-rbf.md), optionally .gz\n"
    "  --eps E               truncation tolerance: each term is cut where |w| exp(...) falls to E, and\n"
    "                        terms with |w| <= E are dropped (default 1e-4 of the largest |w|)\n"
    "  --domain x0,y0,z0,x1,y1,z1   box where rays sample (default: the union of the supports);\n"
    "                        with a bias the field is w0 everywhere else, so the box bounds it\n"
    "  --rbf-leaf N          RBFs per BVH leaf, 1..32 (default 4)\n"
    "  --rbf-canonical-order 0|1   as --canonical-order of particles: 1 (the default) the canonical\n"
    "                        BVH (mpirun's image is this one's bit for bit), 0 Embree's build\n"
    "  --rbf-accel coherent|bvh|octree   what the default method renders through:\n"
    "                        coherent (the default; the fastest in docs/bench/rbf.md, 1.6-4x the others\n"
    "                        in dvr, mip and iso on hydrogen and neghip): 8x8 ray groups walk the BVH of the supports and\n"
    "                        add each term to a buffer of samples along the rays, stepping its\n"
    "                        Gaussian without exp (the particle kernel, Knoll 2014);\n"
    "                        bvh: per sample, gather the terms through the BVH;\n"
    "                        octree: the adaptive octree of Jang 2004 §5 (per-cell RBF lists)\n"
    "  --rbf-cell N          octree: split cells holding more than N RBFs, 1..4096 (default 32);\n"
    "                        builds the octree (the default accel becomes octree)\n"
    "  --rbf-significant     octree: keep only the N most significant RBFs per cell and interpolate\n"
    "                        the dropped terms from the cell corners (approximate; --stats shows the bound)\n"
    "  --method coherent|bvh|brute   force coherent, the BVH gather or every RBF at every sample on any\n"
    "                        set (default: the accel)\n"
    "  defaults: method = the accel (coherent), dt a quarter of the smallest width,\n"
    "  range from the bias w0 to the largest value at the centres (the other way round for a set of\n"
    "  negative terms), so the background is transparent; --stats shows a conservative bound,\n"
    "  TF heat with a peak extinction of 1 / the largest width\n"
    "  example: lanecast render jet.rbf -o jet.png --shade phong --eps 1e-3 --stats\n"
    "           lanecast render jet.rbf -o jet_bvh.png --method bvh --stats   (compare the counters)\n"
    "\n";

static int parse_flag(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first)
{
    const char *a = argv[*i], *v;
    if (!strcmp(a, "--rbf-significant")) {
        if (!*first) *first = a;
        return cli_load_add(load, cmd, "significant", "1") ? -1 : 1;
    }
    if (strcmp(a, "--eps") && strcmp(a, "--domain") && strcmp(a, "--rbf-leaf") && strcmp(a, "--rbf-accel") &&
        strcmp(a, "--rbf-cell") && strcmp(a, "--rbf-canonical-order"))
        return 0;
    if (!*first) *first = a;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    if (!strcmp(a, "--eps")) {
        float e;
        return arg_float(cmd, a, v, 1e-30f, 1e30f, &e) || cli_load_add(load, cmd, "eps", v) ? -1 : 1;
    }
    if (!strcmp(a, "--rbf-canonical-order")) {
        int n;
        return arg_int(cmd, a, v, 0, 1, &n) || cli_load_add(load, cmd, "canonical_order", v) ? -1 : 1;
    }
    if (!strcmp(a, "--rbf-leaf")) {
        int n;
        return arg_int(cmd, a, v, 1, 32, &n) || cli_load_add(load, cmd, "leaf_size", v) ? -1 : 1;
    }
    if (!strcmp(a, "--rbf-cell")) {
        int n;
        return arg_int(cmd, a, v, 1, LC_RBF_MAX_CELL, &n) || cli_load_add(load, cmd, "cell_max", v) ? -1 : 1;
    }
    /* --rbf-accel and --domain: the library checks the value and names the file */
    if (!strcmp(a, "--rbf-accel")) return cli_load_add(load, cmd, "accel", v) ? -1 : 1;
    return cli_load_add(load, cmd, "domain", v) ? -1 : 1;
}

static lc_status apply(lc_volume *v, lc_render_desc *rd)
{
    (void)v, (void)rd; /* RBF sets have no per-render parameters */
    return LC_OK;
}

static lc_status default_tf(lc_device *dev, const lc_volume *v, const cli_tf_req *req, lc_tf **out)
{
    lc_rbf_info ri;
    lc_status s = lc_rbf_get_info(v, &ri);
    if (s != LC_OK) return s;
    float t = req->tau > 0.0f ? req->tau : (ri.max_width > 0.0f ? 1.0f / ri.max_width : 1.0f);
    return lc_tf_preset(dev, req->preset ? req->preset : req->colormap ? req->colormap : "heat", 1, t, out);
}

static void print_stats(const lc_volume *v, double load_seconds, FILE *f)
{
    lc_rbf_info ri;
    if (lc_rbf_get_info(v, &ri) != LC_OK) return;
    fprintf(f, "rbfs          %zu (%zu without support at eps %g), bias %g, width %.4g..%.4g, support <= %.4g\n",
            ri.count, ri.dropped, (double)ri.eps, (double)ri.bias, (double)ri.min_width, (double)ri.max_width,
            (double)ri.max_support);
    fprintf(f, "domain        %g,%g,%g .. %g,%g,%g; range bound %g..%g\n", (double)ri.bounds.lo.x,
            (double)ri.bounds.lo.y, (double)ri.bounds.lo.z, (double)ri.bounds.hi.x, (double)ri.bounds.hi.y,
            (double)ri.bounds.hi.z, (double)ri.range[0], (double)ri.range[1]);
    fprintf(f, "load          %.3f s (reading, BVH build, range bound, octree)\n", load_seconds);
    fprintf(f, "bvh           %d nodes, depth %d, %.2f MB, build %.3f s; RBF data %.2f MB\n", ri.bvh_nodes,
            ri.bvh_depth, (double)ri.bvh_bytes / 1e6, ri.build_seconds, (double)ri.data_bytes / 1e6);
    if (ri.accel == LC_RBF_ACCEL_OCTREE)
        fprintf(f, "octree        %d cells (%d leaves), depth %d, %zu list entries (longest %zu, cell max %d), %.2f MB, "
                   "build %.3f s\n",
                ri.octree_cells, ri.octree_leaves, ri.octree_depth, ri.octree_refs, ri.octree_max_list, ri.cell_max,
                (double)ri.octree_bytes / 1e6, ri.octree_seconds);
    if (ri.significant)
        fprintf(f, "significant   %zu list entries dropped, |f - f_exact| <= %.4g (per-cell bound)\n", ri.truncated,
                ri.truncation_bound);
}

const cli_kind cli_rbf = {LC_KIND_RBF, help, parse_flag, apply, NULL, default_tf, print_stats, "rbf terms    "};
