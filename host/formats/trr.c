/* GROMACS TRR trajectories: full-precision frames in XDR (big-endian).
 * Each frame is a header
 *
 *   int magic 1993, int 13, XDR string "GMX_trn_file" (int length, bytes
 *   padded to 4), int ir_size, e_size, box_size, vir_size, pres_size,
 *   top_size, sym_size, x_size, v_size, f_size, natoms, step, nre,
 *   real time, real lambda
 *
 * then box (9 reals, nm), virial and pressure (9 reals each), positions,
 * velocities and forces (natoms x 3 reals each; nm, nm/ps, kJ/mol/nm), each
 * present when its size is not 0. A real is a float or a double: the size
 * of whichever block is present says which (box_size / 9, x_size / (3
 * natoms), ...), and every present block must agree. ir, e, top and sym
 * blocks are never written by GROMACS 4 or later and are refused.
 *
 * Frames are found from their headers (the sizes give each frame's length),
 * so lc_load_desc.frame seeks without reading earlier frames' data.
 * Positions become Angstrom (x10, as .gro); `value = speed | force` takes
 * each atom's |v| (nm/ps) or |f| (kJ/mol/nm) as k_i. The topology is a
 * companion .gro, .pdb or .psf (topology.h). Errors name the file, the byte
 * and the frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/binfile.h"
#include "host/formats/checked.h"
#include "host/formats/topology.h"
#include "host/formats/xdr.h"

#define TRR_MAGIC 1993
#define TRR_MAX_ATOMS ((int64_t)INT32_MAX / 24)

enum { S_IR, S_E, S_BOX, S_VIR, S_PRES, S_TOP, S_SYM, S_X, S_V, S_F, S_N };
static const char *const size_names[S_N] = {"ir", "e", "box", "vir", "pres", "top", "sym", "x", "v", "f"};

typedef struct trr_frame {
    int64_t off, data, next;
    int32_t size[S_N], natoms, step;
    int real; /* 4 or 8 */
    double time;
} trr_frame;

static lc_status frame_header(lci_bin *b, int64_t off, int64_t k, trr_frame *f, int *eof)
{
    unsigned char h[160];
    char what[64];
    memset(f, 0, sizeof *f);
    f->off = off;
    *eof = 0;
    snprintf(what, sizeof what, "the header of frame %lld", (long long)k);
    if (b->size - off < 12) *eof = 1;
    lc_status s = lci_bin_read(b, off, h, 12, what);
    if (s != LC_OK) return s;
    int32_t magic = lci_bin_i32(b, h), slen = lci_bin_i32(b, h + 4), len = lci_bin_i32(b, h + 8);
    if (magic != TRR_MAGIC)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: magic number %d, expected %d (a TRR frame)",
                         b->path, (long long)off, (long long)k, magic, TRR_MAGIC);
    if (len < 1 || len > 64 || slen != len + 1)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: version string of %d bytes (declared %d), "
                         "expected 12 ('GMX_trn_file')", b->path, (long long)off + 4, (long long)k, len, slen);
    int64_t ints = off + 12 + (len + 3) / 4 * 4;
    if (b->size - ints < 52) *eof = 1;
    if ((s = lci_bin_read(b, ints, h, 52, what)) != LC_OK) return s;
    for (int i = 0; i < S_N; i++) f->size[i] = lci_bin_i32(b, h + 4 * i);
    f->natoms = lci_bin_i32(b, h + 40);
    f->step = lci_bin_i32(b, h + 44);
    if (f->natoms < 0 || f->natoms > TRR_MAX_ATOMS)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: atom count %d, expected 0 to %lld", b->path,
                         (long long)ints + 40, (long long)k, f->natoms, (long long)TRR_MAX_ATOMS);
    for (int i = 0; i < S_N; i++) {
        int legacy = i == S_IR || i == S_E || i == S_TOP || i == S_SYM;
        if (f->size[i] < 0 || (legacy && f->size[i]))
            return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: %s_size %d, expected %s", b->path,
                             (long long)ints + 4 * i, (long long)k, size_names[i], f->size[i],
                             legacy ? "0 (no GROMACS since version 4 writes that block)" : "0 or more");
    }
    /* the real size from the first block present, then every block checked against it */
    int64_t n3 = 3 * (int64_t)f->natoms;
    for (int i = S_BOX; i <= S_F && !f->real; i++) {
        if (!f->size[i] || i == S_TOP || i == S_SYM) continue;
        int64_t per = i <= S_PRES ? 9 : n3;
        if (per > 0 && f->size[i] % per == 0) f->real = (int)(f->size[i] / per);
        if (f->real != 4 && f->real != 8) f->real = -1;
    }
    for (int i = S_BOX; i <= S_F && f->real > 0; i++) {
        int64_t want = (i <= S_PRES ? 9 : n3) * f->real;
        if (f->size[i] && f->size[i] != want) f->real = -1;
    }
    if (f->real <= 0)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: block sizes box %d, x %d, v %d, f %d for %d "
                         "atoms are neither all float nor all double", b->path, (long long)ints + 8, (long long)k,
                         f->size[S_BOX], f->size[S_X], f->size[S_V], f->size[S_F], f->natoms);
    if (b->size - ints - 52 < 2 * f->real) *eof = 1;
    if ((s = lci_bin_read(b, ints + 52, h + 52, (size_t)(2 * f->real), what)) != LC_OK) return s;
    f->time = f->real == 8 ? lci_xdr_f64(h + 52) : lci_xdr_f32(h + 52);
    if (!isfinite(f->time))
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: time %g is not finite", b->path,
                         (long long)ints + 52, (long long)k, f->time);
    f->data = ints + 52 + 2 * f->real;
    int64_t bytes = 0;
    for (int i = 0; i < S_N; i++) bytes += f->size[i];
    f->next = f->data + bytes;
    if (f->next > b->size) {
        *eof = 1;
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: the file ends inside frame %lld (%lld bytes of data "
                         "declared, %lld left)", b->path, (long long)f->data, (long long)k, (long long)bytes,
                         (long long)(b->size - f->data));
    }
    return LC_OK;
}

/* frame_header as an lci_frame_header_fn */
static lc_status header_fn(lci_bin *b, int64_t off, int64_t k, void *frame, int64_t *next, int *eof)
{
    lc_status s = frame_header(b, off, k, frame, eof);
    *next = ((trr_frame *)frame)->next;
    return s;
}

/* Block `which` (x, v or f) of frame k as floats (times scale) into out. */
static lc_status read_block(lci_bin *b, const trr_frame *f, int64_t k, int which, double scale, float *out)
{
    int64_t off = f->data;
    for (int i = 0; i < which; i++) off += f->size[i];
    int64_t n = 3 * (int64_t)f->natoms;
    unsigned char *raw = lci_alloc_checked(b->dev, b->path, (uint64_t)n, (uint64_t)f->real, 0, "atoms", 0);
    if (!raw) return LC_ERROR_OUT_OF_MEMORY;
    char what[64];
    snprintf(what, sizeof what, "the %s block of frame %lld", size_names[which], (long long)k);
    lc_status s = lci_bin_read(b, off, raw, (size_t)(n * f->real), what);
    for (int64_t i = 0; s == LC_OK && i < n; i++) {
        double v = f->real == 8 ? lci_xdr_f64(raw + 8 * i) : lci_xdr_f32(raw + 4 * i);
        if (!isfinite(v))
            s = lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: atom %lld: %s %c = %g is not finite",
                          b->path, (long long)(off + i * f->real), (long long)k, (long long)(i / 3) + 1,
                          size_names[which], "xyz"[i % 3], v);
        out[i] = f->real == 8 ? (float)(v * scale) : (float)v * (float)scale;
    }
    free(raw);
    return s;
}

/* |block| per atom from the three components in xyz (overwritten: n values). */
static void magnitudes(float *xyz, int64_t n)
{
    for (int64_t i = 0; i < n; i++)
        xyz[i] = sqrtf(xyz[3 * i] * xyz[3 * i] + xyz[3 * i + 1] * xyz[3 * i + 1] + xyz[3 * i + 2] * xyz[3 * i + 2]);
}

static lc_status trr_open(lc_device *dev, const char *path, lci_bin *b)
{
    lc_status s = lci_bin_open(dev, path, "TRR trajectories", b);
    if (s == LC_OK) lci_xdr_order(b);
    return s;
}

static lc_status trr_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_bin b;
    lci_topo topo = {0};
    float *xyz = NULL, *vf[2] = {NULL, NULL};
    char why[4300] = "";
    trr_frame f;
    int64_t k = a->desc->frame;
    lc_status s = trr_open(dev, a->path, &b);
    if (s == LC_OK) s = lci_bin_seek_frame(&b, k, header_fn, &f);
    if (s == LC_OK && !f.size[S_X])
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld holds no positions (x_size 0)", a->path,
                      (long long)f.off, (long long)k);
    if (s == LC_OK) s = lci_topo_load(dev, a, ".gro .pdb .psf", &topo, why, sizeof why);
    if (s == LC_OK && !(xyz = lci_alloc_checked(dev, a->path, (uint64_t)f.natoms, 12, 0, "atoms", 0)))
        s = LC_ERROR_OUT_OF_MEMORY;
    if (s == LC_OK) s = read_block(&b, &f, k, S_X, 10.0, xyz); /* nm -> Angstrom */
    const lc_option *val = lci_option_find(a, "value");
    for (int j = 0; j < 2 && s == LC_OK && val; j++) {
        if (!f.size[S_V + j] || strcasecmp(val->value, j ? "force" : "speed")) continue;
        if (!(vf[j] = lci_alloc_checked(dev, a->path, (uint64_t)f.natoms, 12, 0, "atoms", 0))) s = LC_ERROR_OUT_OF_MEMORY;
        else if ((s = read_block(&b, &f, k, S_V + j, 1.0, vf[j])) == LC_OK) magnitudes(vf[j], f.natoms);
    }
    lci_bin_close(&b);
    lci_traj_values vals = {{"speed", "force"}, {vf[0], vf[1]}};
    s = lci_topo_atoms(dev, a, s, &topo, why, xyz, s == LC_OK ? f.natoms : 0, &vals, out);
    free(xyz);
    free(vf[0]);
    free(vf[1]);
    lci_topo_free(&topo);
    return s;
}

static lc_status trr_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_bin b;
    trr_frame f;
    *out = 0;
    lc_status s = trr_open(dev, path, &b);
    if (s == LC_OK) s = lci_bin_count_frames(&b, header_fn, &f, "a TRR frame", out);
    lci_bin_close(&b);
    return s;
}

static int trr_magic(const unsigned char *h, size_t n)
{
    return n >= 24 && !memcmp(h, "\0\0\x07\xc9", 4) && !memcmp(h + 4, "\0\0\0\x0d\0\0\0\x0cGMX_trn_file", 20);
}

const lci_format lci_format_trr = {
    .name = "trr", .kind = LC_KIND_PARTICLES, .extensions = ".trr", .options = "radius radius_scale fields select value",
    .description = "GROMACS TRR trajectory (float or double; positions in nm read as Angstrom, value = speed|force); "
                   "elements from the topology (companion .gro/.pdb/.psf, or STEM.gro, STEM.pdb, STEM.psf)",
    .magic = trr_magic, .read = trr_read, .frames = trr_frames, .companion = 1};
