/* Partial loading of grids for data-parallel rendering (host/mpi/window.c)
 * in one process: for P = 1..4 regions, each region's part is read from
 * files (raw float32, NRRD uint8 attached, NRRD big-endian int16 detached,
 * MetaImage float32, NIfTI-1 uint16 with a flipped and permuted sform)
 * holding only its nodes and ghosts, the parts' leaf brick ranges are
 * united, and the regions rendered from their parts and composited equal
 * the same regions rendered from the whole grid to the bit (dvr with phong
 * shading and pre-integration, mip, iso, slice; three views); the parts'
 * histograms sum to the whole grid's; every part reports the whole grid's
 * info; a part holds fewer nodes than the grid; lc_render of a part and a
 * step longer than the part was loaded for are refused. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "host/formats/volume_data.h"
#include "host/mpi/dp.h"
#include "imgcmp.h"
#include "dp_scene.h"
#include "tmpfiles.h"

enum { NX = 37, NY = 29, NZ = 23, W = 36, H = 28 };
/* a step longer than the files' spacings (0.1 .. 0.25): iso's and
 * pre-integration's previous sample lies cells beyond a region */
#define DT 0.3f

static float field(int i, int j, int k)
{
    float x = (float)i / NX - 0.45f, y = (float)j / NY - 0.55f, z = (float)k / NZ - 0.5f;
    return expf(-6.0f * (x * x + y * y + z * z)) + 0.15f * sinf(0.9f * (float)(i + 2 * j + 3 * k));
}

static void put_u16le(unsigned char *b, int v) { b[0] = (unsigned char)(v & 0xff), b[1] = (unsigned char)(v >> 8); }
static void put_f32(unsigned char *b, float v) { memcpy(b, &v, 4); }

/* The five files; names[i] and their load descs. */
static void write_files(void)
{
    size_t n = (size_t)NX * NY * NZ;
    float *f = malloc(4 * n);
    unsigned char *u8 = malloc(n), *i16 = malloc(2 * n), *u16 = malloc(2 * n);
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                size_t e = ((size_t)k * NY + (size_t)j) * NX + (size_t)i;
                float v = field(i, j, k);
                f[e] = v;
                u8[e] = (unsigned char)lrintf(fminf(fmaxf(v, 0.0f), 1.0f) * 255.0f);
                int s = (int)lrintf(v * 20000.0f) - 3000;
                i16[2 * e] = (unsigned char)((s >> 8) & 0xff), i16[2 * e + 1] = (unsigned char)(s & 0xff); /* big-endian */
            }
    put("g.raw", f, 4 * n);
    char hdr[512];
    snprintf(hdr, sizeof hdr,
             "NRRD0004\ntype: uchar\ndimension: 3\nsizes: %d %d %d\nspacings: 0.1 0.12 0.15\nencoding: raw\n\n", NX, NY,
             NZ);
    FILE *o = fopen(tpath("a.nrrd"), "wb");
    fwrite(hdr, 1, strlen(hdr), o), fwrite(u8, 1, n, o), fclose(o);
    snprintf(hdr, sizeof hdr,
             "NRRD0004\ntype: short\ndimension: 3\nsizes: %d %d %d\nspacings: 0.2 0.2 0.25\nendian: big\n"
             "encoding: raw\ndata file: d.i16\n\n",
             NX, NY, NZ);
    puts_("d.nhdr", hdr);
    put("d.i16", i16, 2 * n);
    snprintf(hdr, sizeof hdr,
             "ObjectType = Image\nNDims = 3\nDimSize = %d %d %d\nElementType = MET_FLOAT\nElementSpacing = 0.1 0.1 "
             "0.1\nOffset = -1 -1.5 -1\nElementDataFile = g.raw\n",
             NX, NY, NZ);
    puts_("m.mhd", hdr);
    /* NIfTI-1: file axes (i, j, k) of sizes NX, NY, NZ onto world (-y, x, z):
     * srow_x = (0, 0.1, 0, -1), srow_y = (-0.2, 0, 0, 2), srow_z = (0, 0, 0.15, 0) */
    unsigned char nh[352];
    memset(nh, 0, sizeof nh);
    int32_t sz = 348;
    memcpy(nh, &sz, 4);
    int16_t dim[8] = {3, NX, NY, NZ, 1, 1, 1, 1};
    for (int d = 0; d < 8; d++) put_u16le(nh + 40 + 2 * d, dim[d]);
    put_u16le(nh + 70, 512), put_u16le(nh + 72, 16); /* DT_UINT16, bitpix */
    float pix[8] = {1, 0.2f, 0.1f, 0.15f, 1, 1, 1, 1};
    for (int d = 0; d < 8; d++) put_f32(nh + 76 + 4 * d, pix[d]);
    put_f32(nh + 108, 352.0f);
    put_u16le(nh + 254, 1); /* sform_code */
    const float srow[3][4] = {{0, 0.1f, 0, -1}, {-0.2f, 0, 0, 2}, {0, 0, 0.15f, 0}};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) put_f32(nh + 280 + 16 * r + 4 * c, srow[r][c]);
    memcpy(nh + 344, "n+1", 4);
    for (size_t e = 0; e < n; e++) put_u16le(u16 + 2 * e, (int)lrintf(fminf(fmaxf(f[e], 0.0f), 1.2f) * 50000.0f));
    o = fopen(tpath("n.nii"), "wb");
    fwrite(nh, 1, sizeof nh, o), fwrite(u16, 1, 2 * n, o), fclose(o);
    free(f), free(u8), free(i16), free(u16);
}

typedef struct fcase {
    const char *file, *format;
    lc_option opt[2];
    int nopt;
} fcase;

/* Every region's part of the file: read, united brick ranges, volumes. */
static int load_parts(lc_device *dev, const char *path, const lc_load_desc *ld, const char *format, int P,
                      lc_grid_layout layout, lc_volume **parts, uint64_t *held)
{
    lci_vol_layout lay;
    if (lci_dp_grid_layout(dev, path, ld, format, &lay) != LC_OK) {
        CHECK(0, "%s: layout: %s", path, lc_device_last_error(dev));
        return -1;
    }
    lc_grid_desc shape = lay.grid;
    shape.layout = layout; /* a kind option: lc_mpi_volume_load applies it so */
    lci_dp_window w[4];
    void *data[4] = {0};
    float *bmin = NULL, *bmax = NULL;
    size_t nb = 0;
    int ok = 1;
    for (int r = 0; r < P && ok; r++) {
        float *mn, *mx;
        ok = lci_dp_grid_plan(dev, &shape, P, r, DT, &w[r]) == LC_OK &&
             lci_dp_grid_read(dev, path, &lay, w[r].start, w[r].count, &data[r]) == LC_OK &&
             lci_dp_grid_ranges(dev, &shape, &w[r], data[r], &mn, &mx, &nb) == LC_OK;
        if (!ok) break;
        held[r] = (uint64_t)w[r].count[0] * (uint64_t)w[r].count[1] * (uint64_t)w[r].count[2];
        if (!bmin) {
            bmin = mn, bmax = mx;
            continue;
        }
        for (size_t i = 0; i < nb; i++) bmin[i] = fminf(bmin[i], mn[i]), bmax[i] = fmaxf(bmax[i], mx[i]);
        free(mn), free(mx);
    }
    for (int r = 0; r < P && ok; r++)
        ok = lci_dp_grid_create(dev, &shape, &w[r], data[r], bmin, bmax, P, r, NULL, NULL, NULL, &parts[r]) == LC_OK;
    if (!ok) CHECK(0, "%s P=%d: parts: %s", path, P, lc_device_last_error(dev));
    for (int r = 0; r < P; r++) free(data[r]);
    free(bmin), free(bmax);
    return ok ? 0 : -1;
}

/* Regions of the whole grid and of the parts, composited; equal to the bit. */
static void compare(lc_device *dev, const char *label, const lc_volume *whole, lc_volume *const *parts, int P,
                    const lc_tf *tf, lc_mode mode, int vi)
{
    lc_render_desc d = dp_desc(whole, tf, mode, vi, 1.0f, W, H, 0.5f);
    d.dt = DT;
    d.shading = mode == LC_MODE_DVR || mode == LC_MODE_ISO ? LC_SHADE_PHONG : LC_SHADE_NONE;
    size_t np = (size_t)W * H;
    float *want = malloc(sizeof(float) * 4 * np), *got = malloc(sizeof(float) * 4 * np);
    lc_status s = lci_dp_render_local(dev, &d, P, want, NULL, NULL);
    if (s == LC_OK) s = dp_render_parts(dev, &d, parts, P, got);
    CHECK_QUIET(s == LC_OK, "%s %s %s P=%d: %s", label, dp_mode_names[mode], dp_view_names[vi], P,
                lc_device_last_error(dev));
    if (s == LC_OK)
        CHECK_QUIET(memcmp(got, want, sizeof(float) * 4 * np) == 0, "%s %s %s P=%d: parts' image != whole grid's",
                    label, dp_mode_names[mode], dp_view_names[vi], P);
    free(want), free(got);
}

static void check_info(const char *label, const lc_volume *whole, lc_volume *const *parts, int P)
{
    lc_grid_info a, b;
    lc_grid_get_info(whole, &a);
    enum { NB = 64 };
    uint64_t hw[NB], hp[NB], sum[NB] = {0};
    lc_grid_histogram(whole, NB, hw);
    int same = 1;
    for (int r = 0; r < P; r++) {
        lc_grid_get_info(parts[r], &b);
        same &= !memcmp(a.size, b.size, sizeof a.size) && !memcmp(&a.bounds, &b.bounds, sizeof a.bounds) &&
                a.value_min == b.value_min && a.value_max == b.value_max && a.bvh_nodes == b.bvh_nodes;
        lc_grid_histogram(parts[r], NB, hp);
        for (int i = 0; i < NB; i++) sum[i] += hp[i];
    }
    CHECK_QUIET(same, "%s P=%d: a part's info (size, bounds, value range, BVH nodes) differs from the whole grid's", label, P);
    CHECK_QUIET(!memcmp(sum, hw, sizeof hw), "%s P=%d: the parts' histograms do not sum to the whole grid's", label, P);
}

int main(void)
{
    char dir[] = "/tmp/lc_dp_load_XXXXXX";
    if (!mkdtemp(dir)) return 1;
    tmp = dir;
    write_files();
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    static const float col[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.5f, 1.0f, 0.4f, 0.1f, 1.0f, 1.0f, 1.0f, 0.8f};
    static const float op[] = {0.0f, 0.0f, 0.3f, 1.0f, 1.0f, 6.0f};
    char dims[64];
    snprintf(dims, sizeof dims, "%d,%d,%d", NX, NY, NZ);
    fcase cases[] = {
        {"g.raw", "raw-volume", {{"size", dims}, {"type", "float32"}}, 2},
        {"a.nrrd", "nrrd", {{0}}, 0},
        {"d.nhdr", "nrrd", {{"layout", "bricked"}}, 1},
        {"m.mhd", "metaimage", {{0}}, 0},
        {"n.nii", "nifti", {{0}}, 0},
    };
    int ncases = LC_HAVE_NIFTI ? 5 : 4;
    if (!LC_HAVE_NIFTI) printf("note: built without NIfTI (libnifti2-dev): the NIfTI case is skipped\n");
    for (int c = 0; c < ncases; c++) {
        const char *path = tpath(cases[c].file);
        lc_load_desc ld = {.options = cases[c].opt, .noptions = cases[c].nopt};
        lc_volume *whole = NULL;
        if (lc_volume_load(dev, path, &ld, &whole) != LC_OK) {
            CHECK(0, "%s: %s", path, lc_device_last_error(dev));
            continue;
        }
        lc_grid_info gi;
        lc_grid_get_info(whole, &gi);
        lc_tf_field tff = {col, 3, op, 3, 1, {gi.value_min, gi.value_max}};
        lc_tf *tf = NULL;
        lc_tf_create(dev, &tff, 1, &tf);
        int before = check_failures;
        for (int P = 1; P <= 4; P++) {
            lc_volume *parts[4] = {0};
            uint64_t held[4] = {0};
            /* the bricked layout is a kind option: the whole load took it from ld */
            lc_load_desc lp = ld;
            lc_option fo[2];
            lp.noptions = 0, lp.options = fo;
            for (int i = 0; i < ld.noptions; i++)
                if (strcmp(ld.options[i].key, "layout")) fo[lp.noptions++] = ld.options[i];
            lc_grid_layout layout = c == 2 ? LC_LAYOUT_BRICKED : LC_LAYOUT_DEFAULT;
            if (load_parts(dev, path, &lp, cases[c].format, P, layout, parts, held) != 0) continue;
            uint64_t all = (uint64_t)NX * NY * NZ;
            for (int r = 0; P > 1 && r < P; r++)
                CHECK_QUIET(held[r] < all, "%s P=%d: part %d holds %llu of %llu nodes", path, P, r,
                            (unsigned long long)held[r], (unsigned long long)all);
            check_info(path, whole, parts, P);
            static const lc_mode modes[] = {LC_MODE_DVR, LC_MODE_MIP, LC_MODE_ISO, LC_MODE_SLICE};
            for (int m = 0; m < 4; m++)
                for (int vi = 0; vi < 3; vi++) compare(dev, path, whole, parts, P, tf, modes[m], vi);
            if (P == 2) {
                lc_grid_params gp = {.preintegrated = 1};
                lc_grid_set_params(whole, &gp);
                for (int r = 0; r < P; r++) lc_grid_set_params(parts[r], &gp);
                compare(dev, "preintegrated", whole, parts, P, tf, LC_MODE_DVR, 0);
                lc_grid_set_params(whole, &(lc_grid_params){0});
                /* a part alone, and a longer step than it was loaded for */
                lc_render_desc d = dp_desc(parts[0], tf, LC_MODE_DVR, 0, 1.0f, 8, 8, 0.0f);
                d.dt = DT;
                float img[4 * 64];
                lc_status s = lc_render(dev, &d, img, NULL);
                CHECK_QUIET(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "lc_mpi_render"),
                            "%s: lc_render of a part: %s", path, lc_device_last_error(dev));
                lci_kdtree t;
                lci_cimage img2;
                d.dt = 5.0f; /* beyond the ghosts of a 0.3 step at spacings up to 1 */
                lci_dp_partition(dev, &d, P, &t);
                s = lci_dp_render_region(dev, &d, &t, 0, &img2, NULL);
                CHECK_QUIET(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "lacks nodes"),
                            "%s: dt 5 on a part loaded for 0.3: %s", path, lc_device_last_error(dev));
                lci_kd_release(&t);
            }
            for (int r = 0; r < P; r++) lc_volume_destroy(parts[r]);
        }
        CHECK(check_failures == before,
              "%s (%s): parts of P = 1..4 regions hold fewer nodes, report the whole grid, sum to its histogram, "
              "and render its regions to the bit (dvr phong, pre-integrated, mip, iso, slice; 3 views)",
              cases[c].file, cases[c].format);
        lc_tf_destroy(tf);
        lc_volume_destroy(whole);
    }
    /* compressed data is read whole (the caller falls back) */
    static const unsigned char gz[] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    char hdr[256];
    snprintf(hdr, sizeof hdr, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\ndata file: z.gz\n\n");
    puts_("z.nhdr", hdr);
    put("z.gz", gz, sizeof gz);
    lci_vol_layout lay;
    lc_status s = lci_dp_grid_layout(dev, tpath("z.nhdr"), NULL, "nrrd", &lay);
    CHECK(s == LC_ERROR_UNSUPPORTED, "gzip NRRD: read whole (%s)", lc_device_last_error(dev));
    lc_device_destroy(dev);
    const char *names[] = {"g.raw", "a.nrrd", "d.nhdr", "d.i16", "m.mhd", "n.nii", "z.nhdr", "z.gz"};
    for (int i = 0; i < 8; i++) unlink(tpath(names[i]));
    rmdir(dir);
    return check_summary("test_dp_load");
}
