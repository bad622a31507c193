/* NIfTI-1 and NIfTI-2 volumes (.nii, .nii.gz, .hdr/.img pairs) through
 * nifti_clib (libnifti2), which reads either version and byte order,
 * gzip, and turns the quaternion qform and the sform into matrices.
 *
 * This file first checks the header itself (so errors name the byte), then
 * has the library read one 3-D brick: a 4-D file's volumes are frames.
 * Values: uint8, int16, uint16 and float32 stay as they are; int8, int32,
 * uint32, int64, uint64 and float64 become float32 (a note says so); a
 * scaling (scl_slope != 0 and not the identity) is applied, in float32.
 *
 * Orientation. The voxel-to-world matrix is the sform when sform_code > 0,
 * else the qform when qform_code > 0, else the voxel sizes alone (NIfTI's
 * "method 1"). lanecast grids are axis-aligned with x fastest, so each
 * voxel axis is mapped onto a world axis: the permutation (of the six) that
 * puts the most of each axis onto its world axis, with a flip where the
 * component is negative; the voxels are reordered so that the grid's x, y,
 * z are world x, y, z, increasing. When the matrix is such a permutation
 * with flips and scales (every other component below 1e-6 of its column),
 * every voxel lands exactly where the file puts it. An oblique matrix is
 * replaced by the nearest axis-aligned frame: voxel sizes (column lengths)
 * and the volume's centre are kept, and a warning gives the largest angle
 * between a voxel axis and the world axis it was put on. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/formats/orient.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"

#if LC_HAVE_NIFTI
#include <nifti2_io.h>
#include <sys/stat.h>

/* What this file reads from the header itself. */
typedef struct nhead {
    int version; /* 1 or 2; 0 = Analyze 7.5 (no magic) */
    int swap;
    int64_t dim[8];
    int datatype;
    double vox_offset;
    int single; /* one .nii file */
    int off_dim, off_type, off_vox; /* byte offsets of those fields */
} nhead;

static uint64_t raw(const unsigned char *p, int n, int swap)
{
    uint64_t u = 0;
    for (int i = 0; i < n; i++) u |= (uint64_t)p[swap ? n - 1 - i : i] << (8 * i);
    return u;
}
static int64_t i16(const unsigned char *p, int swap) { return (int16_t)raw(p, 2, swap); }
static int64_t i64(const unsigned char *p, int swap) { return (int64_t)raw(p, 8, swap); }
static double f32(const unsigned char *p, int swap)
{
    uint32_t w = (uint32_t)raw(p, 4, swap);
    float f;
    memcpy(&f, &w, 4);
    return f;
}

typedef struct ntype {
    int code;
    const char *name;
    int bytes;
    lc_value_type to;
} ntype;

static const ntype ntypes[] = {
    {DT_UINT8, "uint8", 1, LC_VALUE_UINT8},       {DT_INT16, "int16", 2, LC_VALUE_INT16},
    {DT_UINT16, "uint16", 2, LC_VALUE_UINT16},    {DT_FLOAT32, "float32", 4, LC_VALUE_FLOAT32},
    {DT_INT8, "int8", 1, LC_VALUE_FLOAT32},       {DT_INT32, "int32", 4, LC_VALUE_FLOAT32},
    {DT_UINT32, "uint32", 4, LC_VALUE_FLOAT32},   {DT_INT64, "int64", 8, LC_VALUE_FLOAT32},
    {DT_UINT64, "uint64", 8, LC_VALUE_FLOAT32},   {DT_FLOAT64, "float64", 8, LC_VALUE_FLOAT32},
};

static const ntype *ntype_of(int code)
{
    for (size_t i = 0; i < sizeof ntypes / sizeof ntypes[0]; i++)
        if (ntypes[i].code == code) return &ntypes[i];
    return NULL;
}

#define BAD(...) lci_error(dev, LC_ERROR_FORMAT, __VA_ARGS__)

/* Reads and checks the header of path (plain or gzip). */
static lc_status read_head(lc_device *dev, const char *path, nhead *h)
{
    memset(h, 0, sizeof *h);
    unsigned char b[540];
    memset(b, 0, sizeof b);
    znzFile z = znzopen(path, "rb", 1);
    if (znz_isnull(z)) return lci_error(dev, LC_ERROR_IO, "%s: cannot open", path);
    size_t n = znzread(b, 1, sizeof b, z);
    znzclose(z);
    if (n < 348) return BAD("%s: byte %zu: the file ends inside the 348-byte NIfTI-1 header", path, n);
    int64_t sz = (int32_t)raw(b, 4, 0);
    if (sz == 348 || sz == 540) h->swap = 0;
    else if ((int32_t)raw(b, 4, 1) == 348 || (int32_t)raw(b, 4, 1) == 540) h->swap = 1, sz = (int32_t)raw(b, 4, 1);
    else return BAD("%s: byte 0: sizeof_hdr is %lld, expected 348 (NIfTI-1) or 540 (NIfTI-2)", path, (long long)sz);
    int s = h->swap;
    if (sz == 540) {
        if (n < 540) return BAD("%s: byte %zu: the file ends inside the 540-byte NIfTI-2 header", path, n);
        if (memcmp(b + 4, "n+2", 4) && memcmp(b + 4, "ni2", 4))
            return BAD("%s: byte 4: magic '%.3s', expected 'n+2' or 'ni2' after sizeof_hdr 540", path, (const char *)b + 4);
        h->version = 2;
        h->single = b[5] == '+';
        h->off_dim = 16, h->off_type = 12, h->off_vox = 168;
        for (int k = 0; k < 8; k++) h->dim[k] = i64(b + 16 + 8 * k, s);
        h->datatype = (int)i16(b + 12, s);
        h->vox_offset = (double)i64(b + 168, s);
    } else {
        h->version = !memcmp(b + 344, "n+1", 4) || !memcmp(b + 344, "ni1", 4) ? 1 : 0;
        if (!h->version && b[344]) /* Analyze 7.5 has no magic; anything else is damage */
            return BAD("%s: byte 344: magic '%.3s', expected 'n+1' or 'ni1'", path, (const char *)b + 344);
        h->single = h->version == 1 && b[345] == '+';
        h->off_dim = 40, h->off_type = 70, h->off_vox = 108;
        for (int k = 0; k < 8; k++) h->dim[k] = i16(b + 40 + 2 * k, s);
        h->datatype = (int)i16(b + 70, s);
        h->vox_offset = f32(b + 108, s);
    }
    if (h->dim[0] < 3 || h->dim[0] > 7)
        return BAD("%s: byte %d: dim[0] = %lld, expected 3 to 7 (lanecast reads 3-D volumes, 4-D as frames)", path,
                   h->off_dim, (long long)h->dim[0]);
    for (int k = 1; k <= h->dim[0]; k++)
        if (h->dim[k] < 1 || h->dim[k] > INT32_MAX)
            return BAD("%s: byte %d: dim[%d] = %lld, expected 1 to 2^31-1", path, h->off_dim + k * (h->version == 2 ? 8 : 2),
                       k, (long long)h->dim[k]);
    for (int k = h->dim[0] + 1; k < 8; k++) h->dim[k] = 1;
    for (int k = 1; k <= 3; k++)
        if (h->dim[k] < 2)
            return BAD("%s: byte %d: dim[%d] = %lld: lanecast grids need 2 or more nodes along each axis", path,
                       h->off_dim + k * (h->version == 2 ? 8 : 2), k, (long long)h->dim[k]);
    for (int k = 5; k < 8; k++)
        if (h->dim[k] > 1)
            return BAD("%s: byte %d: dim[%d] = %lld: vector or multi-component voxels are not read (scalars only)", path,
                       h->off_dim + k * (h->version == 2 ? 8 : 2), k, (long long)h->dim[k]);
    const ntype *t = ntype_of(h->datatype);
    if (!t)
        return BAD("%s: byte %d: datatype %d is not read (uint8, int8, int16, uint16, int32, uint32, int64, uint64, "
                   "float32, float64)", path, h->off_type, h->datatype);
    uint64_t voxels = (uint64_t)h->dim[1] * (uint64_t)h->dim[2] * (uint64_t)h->dim[3];
    if (voxels > INT32_MAX - 64)
        return BAD("%s: byte %d: %lld x %lld x %lld voxels, more than 2^31", path, h->off_dim, (long long)h->dim[1],
                   (long long)h->dim[2], (long long)h->dim[3]);
    if (h->single && (!(h->vox_offset >= (h->version == 2 ? 540 : 348)) || h->vox_offset > 1e15))
        return BAD("%s: byte %d: vox_offset %g lies inside the header", path, h->off_vox, h->vox_offset);
    /* the library reads a whole frame before lanecast sees it: the memory limit first */
    uint64_t frame_bytes;
    if (lci_size_check(dev, path, voxels, (uint64_t)t->bytes, 0, "voxels", &frame_bytes) != LC_OK)
        return LC_ERROR_OUT_OF_MEMORY;
    /* the voxels must fit in what the file holds: exactly for a plain .nii,
       within deflate's largest ratio (1032:1) for a gzip one */
    struct stat st;
    /* a header/image pair too (fuzz_nifti: an Analyze header in a .nii, read
       by nifti_clib as one file, allocated 525 MB for 380 bytes): the file
       nifti_clib will read the voxels from */
    char *img = h->single ? NULL
                          : nifti_findimgname(path, h->version == 2   ? NIFTI_FTYPE_NIFTI2_2
                                                    : h->version == 1 ? NIFTI_FTYPE_NIFTI1_2
                                                                      : NIFTI_FTYPE_ANALYZE);
    char data[4096];
    snprintf(data, sizeof data, "%s", img ? img : path);
    free(img);
    if (stat(data, &st) == 0) {
        if (!h->single && !(h->vox_offset >= 0.0)) h->vox_offset = 0.0;
        uint64_t need = voxels * (uint64_t)h->dim[4] * (uint64_t)t->bytes;
        FILE *f = fopen(data, "rb");
        unsigned char m[2] = {0, 0};
        int gz = f && fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
        if (f) fclose(f);
        if (!gz && (double)st.st_size < h->vox_offset + (double)need)
            return BAD("%s: byte %lld: the file ends before the %llu bytes of voxels that start at vox_offset %g "
                       "(dims and datatype %s)", data, (long long)st.st_size, (unsigned long long)need, h->vox_offset,
                       t->name);
        if (gz && (double)need > 1032.0 * (double)st.st_size)
            return BAD("%s: byte %d: %llu bytes of voxels cannot come from %lld gzip bytes in %s", path, h->off_dim,
                       (unsigned long long)need, (long long)st.st_size, data);
    }
    return LC_OK;
}

/* The grid's frame from the sform, qform or voxel sizes (axis_frame),
 * warning when it is oblique. */
static lc_status grid_frame(lc_device *dev, const char *path, const nifti_image *nim, const int64_t n[3], int perm[3],
                            int flip[3], double spacing[3], double origin[3])
{
    double m[3][4];
    const char *which = nim->sform_code > 0 ? "sform" : nim->qform_code > 0 ? "qform" : "voxel sizes";
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++)
            m[r][c] = nim->sform_code > 0 ? nim->sto_xyz.m[r][c]
                    : nim->qform_code > 0 ? nim->qto_xyz.m[r][c]
                    : (r == c ? (nim->pixdim[r + 1] > 0 ? nim->pixdim[r + 1] : 1.0) : 0.0);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++)
            if (!isfinite(m[r][c])) return BAD("%s: the %s matrix is not finite", path, which);
    double angle = lci_axis_frame((const double(*)[4])m, n, perm, flip, spacing, origin);
    if (angle > 0.0)
        lci_log(dev, LC_LOG_WARNING,
                "%s: the %s is oblique (up to %.2f degrees off the axes); lanecast grids are axis-aligned, so the "
                "nearest axis-aligned frame is used (voxel sizes and the volume's centre kept)",
                path, which, angle);
    return LC_OK;
}

static double value_at(const ntype *t, const void *p, uint64_t i)
{
    switch (t->code) {
    case DT_UINT8: return ((const uint8_t *)p)[i];
    case DT_INT8: return ((const int8_t *)p)[i];
    case DT_INT16: return ((const int16_t *)p)[i];
    case DT_UINT16: return ((const uint16_t *)p)[i];
    case DT_INT32: return ((const int32_t *)p)[i];
    case DT_UINT32: return ((const uint32_t *)p)[i];
    case DT_INT64: return (double)((const int64_t *)p)[i];
    case DT_UINT64: return (double)((const uint64_t *)p)[i];
    case DT_FLOAT32: return ((const float *)p)[i];
    default: return ((const double *)p)[i];
    }
}

static lc_status nifti_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    if (s != LC_OK) return s;
    nhead h;
    if ((s = read_head(dev, a->path, &h)) != LC_OK) return s;
    int64_t frame = a->desc->frame;
    if (frame >= h.dim[4])
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld volume%s",
                         a->path, (long long)frame, (long long)h.dim[4], h.dim[4] > 1 ? "s" : "");
    nifti_set_debug_level(0);
    nifti_brick_list nbl;
    memset(&nbl, 0, sizeof nbl);
    nifti_image *nim = nifti_image_read_bricks(a->path, 1, &frame, &nbl);
    if (!nim || nbl.nbricks != 1 || !nbl.bricks || !nbl.bricks[0]) {
        if (nim) nifti_free_NBL(&nbl), nifti_image_free(nim);
        return BAD("%s: byte %.0f: nifti_clib could not read volume %lld of the voxels (truncated or damaged data)",
                   a->path, h.vox_offset, (long long)frame);
    }
    const ntype *t = ntype_of(nim->datatype);
    int64_t n[3] = {nim->nx, nim->ny, nim->nz};
    uint64_t count = (uint64_t)n[0] * (uint64_t)n[1] * (uint64_t)n[2];
    void *data = NULL;
    lc_grid_desc *d = NULL;
    if (!t || n[0] != h.dim[1] || n[1] != h.dim[2] || n[2] != h.dim[3] || (uint64_t)nbl.bsize != count * (uint64_t)t->bytes) {
        s = lci_error(dev, LC_ERROR_INTERNAL, "%s: nifti_clib's image disagrees with the header", a->path);
        goto out;
    }
    double slope = nim->scl_slope, inter = nim->scl_inter;
    int scaled = slope != 0.0 && isfinite(slope) && isfinite(inter) && !(slope == 1.0 && inter == 0.0);
    lc_value_type to = scaled ? LC_VALUE_FLOAT32 : t->to;
    if (o.type != LC_VALUE_DEFAULT && o.type != to) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the voxels' type (%s%s) differs from the requested one",
                      a->path, t->name, scaled ? ", scaled to float32" : "");
        goto out;
    }
    int perm[3], flip[3];
    double spacing[3], origin[3];
    if ((s = grid_frame(dev, a->path, nim, n, perm, flip, spacing, origin)) != LC_OK) goto out;
    if (t->to == LC_VALUE_FLOAT32 && t->code != DT_FLOAT32)
        lci_log(dev, LC_LOG_INFO, "%s: %s voxels read as float32", a->path, t->name);
    /* reorder (and convert) into world x, y, z, increasing */
    int es = lci_value_size(to);
    if (!(data = lci_alloc_checked(dev, a->path, count, (uint64_t)es, 64, "voxels", 0))) {
        s = LC_ERROR_OUT_OF_MEMORY;
        goto out;
    }
    uint64_t stride[3] = {1, (uint64_t)n[0], (uint64_t)n[0] * (uint64_t)n[1]};
    int64_t on[3] = {n[perm[0]], n[perm[1]], n[perm[2]]};
    const void *src = nbl.bricks[0];
    uint64_t o_i = 0;
    for (int64_t w2 = 0; w2 < on[2]; w2++)
        for (int64_t w1 = 0; w1 < on[1]; w1++)
            for (int64_t w0 = 0; w0 < on[0]; w0++, o_i++) {
                int64_t u[3] = {w0, w1, w2};
                uint64_t si = 0;
                for (int w = 0; w < 3; w++)
                    si += (uint64_t)(flip[w] ? on[w] - 1 - u[w] : u[w]) * stride[perm[w]];
                if (!scaled && t->to != LC_VALUE_FLOAT32) {
                    memcpy((char *)data + o_i * (uint64_t)es, (const char *)src + si * (uint64_t)es, (size_t)es);
                    continue;
                }
                double v = value_at(t, src, si);
                if (scaled) v = v * slope + inter;
                if (!isfinite(v) || fabs(v) > 3.4e38) {
                    s = BAD("%s: byte %.0f: voxel %llu is %g%s, not a finite float32", a->path,
                            h.vox_offset + (double)((uint64_t)frame * count + si) * t->bytes, (unsigned long long)si, v,
                            scaled ? " after scaling" : "");
                    goto out;
                }
                ((float *)data)[o_i] = (float)v;
            }
    if (!(d = calloc(1, sizeof *d))) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
        goto out;
    }
    s = lci_vol_hand_over(dev, a->path, d, on, to, spacing, origin, &o, data, out);
    data = NULL; /* out keeps it */
out:
    free(data);
    nifti_free_NBL(&nbl);
    nifti_image_free(nim);
    return s;
}

lc_status lci_nifti_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l)
{
    memset(l, 0, sizeof *l);
    nhead h;
    lc_status s = read_head(dev, a->path, &h);
    if (s != LC_OK) return s;
    int64_t frame = a->desc->frame;
    if (frame >= h.dim[4])
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld volume%s",
                         a->path, (long long)frame, (long long)h.dim[4], h.dim[4] > 1 ? "s" : "");
    nifti_set_debug_level(0);
    nifti_image *nim = nifti_image_read(a->path, 0); /* the header only */
    if (!nim) return BAD("%s: nifti_clib could not read the header", a->path);
    const ntype *t = ntype_of(nim->datatype);
    double slope = nim->scl_slope, inter = nim->scl_inter;
    int scaled = slope != 0.0 && isfinite(slope) && isfinite(inter) && !(slope == 1.0 && inter == 0.0);
    int gz = 1;
    FILE *f = nim->iname ? fopen(nim->iname, "rb") : NULL;
    unsigned char mg[2] = {0, 0};
    if (f) gz = fread(mg, 1, 2, f) != 2 || (mg[0] == 0x1f && mg[1] == 0x8b), fclose(f);
    int native = t && !scaled && (t->to != LC_VALUE_FLOAT32 || t->code == DT_FLOAT32); /* read as stored */
    if (gz || !native || (o->type != LC_VALUE_DEFAULT && o->type != t->to)) {
        nifti_image_free(nim);
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: compressed, scaled or converted voxels are read whole", a->path);
    }
    int64_t n[3] = {nim->nx, nim->ny, nim->nz};
    int perm[3], flip[3];
    double spacing[3], origin[3];
    s = grid_frame(dev, a->path, nim, n, perm, flip, spacing, origin);
    if (s == LC_OK) {
        snprintf(l->data_path, sizeof l->data_path, "%s", nim->iname);
        l->offset = (long long)nim->iname_offset + (long long)frame * n[0] * n[1] * n[2] * t->bytes;
        l->swap = nim->byteorder != nifti_short_order();
        int64_t on[3];
        for (int w = 0; w < 3; w++) l->fsize[w] = n[w], l->perm[w] = perm[w], l->flip[w] = flip[w], on[w] = n[perm[w]];
        s = lci_vol_layout_grid(dev, a->path, on, t->to, spacing, origin, o, l);
    }
    nifti_image_free(nim);
    return s;
}

/* Frames: the volumes of a 4-D file (dim[4]). */
static lc_status nifti_frames(lc_device *dev, const char *path, int64_t *out)
{
    nhead h;
    *out = 0;
    lc_status s = read_head(dev, path, &h);
    if (s == LC_OK) *out = h.dim[4];
    return s;
}
#define NIFTI_READ nifti_read
#define NIFTI_FRAMES nifti_frames
#else
#define NIFTI_READ NULL
#define NIFTI_FRAMES NULL
lc_status lci_nifti_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l)
{
    (void)o, (void)l;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: NIfTI needs libnifti2-dev", a->path);
}
#endif

/* NIfTI-1 (sizeof_hdr 348, magic at 344) or NIfTI-2 (540, magic at 4), either byte order. */
static int nifti_magic(const unsigned char *h, size_t n)
{
    if (n >= 348 && (!memcmp(h + 344, "n+1", 4) || !memcmp(h + 344, "ni1", 4))) return 1;
    return n >= 12 && (!memcmp(h + 4, "n+2\0\r\n\032\n", 8) || !memcmp(h + 4, "ni2\0\r\n\032\n", 8));
}

const lci_format lci_format_nifti = {
    .name = "nifti", .kind = LC_KIND_GRID, .extensions = ".nii .hdr", .options = "type spacing origin",
    .description = "NIfTI-1/2 (.nii, .nii.gz, .hdr/.img): scaled, oriented onto the nearest axis-aligned frame; "
                   "4-D volumes as frames",
    .magic = nifti_magic, .read = NIFTI_READ, .package = "libnifti2-dev", .frames = NIFTI_FRAMES};
