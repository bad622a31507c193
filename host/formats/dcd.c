/* CHARMM/NAMD/X-PLOR DCD trajectories with a PSF topology as companion.
 *
 * A DCD file is Fortran unformatted records (a length marker, the data, the
 * marker again; 4-byte markers, or 8-byte ones from some old compilers), in
 * either byte order (found from the first marker, which must say 84):
 *
 *   1. "CORD" and 20 int32 ICNTRL: [0] frames (often stale: the frames are
 *      counted from the file size), [8] fixed atoms NAMNF, [9] the time step
 *      (float in CHARMM files, a double over [9..10] in X-PLOR ones), and in
 *      CHARMM files ([19] = CHARMM version != 0) [10] = 1 when every frame
 *      has a unit-cell record and [11] = 1 for a fourth (4D) coordinate;
 *   2. the title: int32 count, then 80-character lines;
 *   3. int32 atom count N;
 *   4. with fixed atoms: the N - NAMNF free atoms' 1-based indices;
 *   then per frame: [unit cell: 6 doubles, 48 bytes], X, Y, Z (and W in 4D
 *   files) as N float32 each (Angstrom) in the first frame, and as N - NAMNF
 *   (the free atoms only) in every later frame.
 *
 * lc_load_desc.frame picks a frame; frames are found by seeking. The
 * companion (lc_load_desc.companion: a PSF, or a .gro or PDB file; else
 * STEM.psf next to the DCD) gives each atom its element, hence its radius
 * (elements.h) and, with `fields = element`, its field; `fields =
 * column:NAME` maps any PSF column (segid, resid, resname, name, type,
 * charge, mass, element) to fields and `value = mass | charge | resid` takes
 * k_i from the PSF (topology.h). Without a topology every atom gets one
 * radius and a warning says why. Every error names the file and byte. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/binfile.h"
#include "host/formats/topology.h"

#define DCD_MAX_ATOMS ((int64_t)INT32_MAX / 2)

typedef struct dcd {
    lci_bin b;
    int charmm, cell, ncoord; /* ncoord: 3, or 4 in 4D files */
    int64_t natom, nfree, nset;
    int32_t *free_idx;        /* 0-based indices of the free atoms (fixed-atom files), else NULL */
    int64_t first, frame0, frame; /* offset of frame 0, bytes of frame 0 and of each later frame */
    int64_t nframes, tail;    /* complete frames; bytes after the last complete one */
} dcd;

static lc_status header(lc_device *dev, const char *path, dcd *d)
{
    memset(d, 0, sizeof *d);
    lc_status s = lci_bin_open(dev, path, "DCD trajectories", &d->b);
    if (s != LC_OK) return s;
    lci_bin *b = &d->b;
    unsigned char h[12];
    if (b->size < 12 || (s = lci_bin_read(b, 0, h, 12, "the header")) != LC_OK)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 0: %lld bytes is too short for a DCD header", path,
                         (long long)b->size);
    static const unsigned char le4[4] = {84, 0, 0, 0}, be4[4] = {0, 0, 0, 84};
    static const unsigned char le8[8] = {84, 0, 0, 0, 0, 0, 0, 0}, be8[8] = {0, 0, 0, 0, 0, 0, 0, 84};
    int little = 1;
    little = *(unsigned char *)&little;
    if (!memcmp(h + 4, "CORD", 4) && (!memcmp(h, le4, 4) || !memcmp(h, be4, 4))) {
        b->marker = 4;
        b->swap = (h[0] == 84) != little;
    } else if (!memcmp(h + 8, "CORD", 4) && (!memcmp(h, le8, 8) || !memcmp(h, be8, 8))) {
        b->marker = 8;
        b->swap = (h[0] == 84) != little;
    } else {
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: byte 0: not a DCD file: expected a record of 84 bytes starting with 'CORD'", path);
    }
    int64_t len, off;
    unsigned char r1[84];
    if ((s = lci_bin_record(b, 0, 84, "the DCD header (CORD)", &len, &off)) != LC_OK ||
        (s = lci_bin_read(b, b->marker, r1, 84, "the DCD header")) != LC_OK)
        return s;
    int32_t ic[20];
    for (int i = 0; i < 20; i++) ic[i] = lci_bin_i32(b, r1 + 4 + 4 * i);
    d->nset = ic[0];
    d->charmm = ic[19] != 0;
    d->cell = d->charmm && ic[10] != 0;
    d->ncoord = d->charmm && ic[11] != 0 ? 4 : 3;
    int64_t namnf = ic[8];
    /* the title */
    int64_t tpos = off;
    if ((s = lci_bin_record(b, tpos, -1, "the title", &len, &off)) != LC_OK) return s;
    if (len < 4)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: a title record of %lld bytes, expected at least 4",
                         path, (long long)tpos, (long long)len);
    /* the atom count */
    int64_t npos = off;
    unsigned char nb[4];
    if ((s = lci_bin_record(b, npos, 4, "the atom count", &len, &off)) != LC_OK ||
        (s = lci_bin_read(b, npos + b->marker, nb, 4, "the atom count")) != LC_OK)
        return s;
    d->natom = lci_bin_i32(b, nb);
    if (d->natom <= 0 || d->natom > DCD_MAX_ATOMS || d->natom * 12 > b->size)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: atom count %lld, expected 1 to %lld (a %lld-byte file)",
                         path, (long long)(npos + b->marker), (long long)d->natom,
                         (long long)(b->size / 12 < DCD_MAX_ATOMS ? b->size / 12 : DCD_MAX_ATOMS), (long long)b->size);
    if (namnf < 0 || namnf >= d->natom)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %d: %lld fixed atoms (ICNTRL(9)) of %lld, expected 0 to %lld",
                         path, b->marker + 36, (long long)namnf, (long long)d->natom, (long long)d->natom - 1);
    d->nfree = d->natom - namnf;
    if (namnf > 0) {
        int64_t fpos = off;
        if ((s = lci_bin_record(b, fpos, 4 * d->nfree, "the free-atom indices", &len, &off)) != LC_OK) return s;
        d->free_idx = malloc(sizeof *d->free_idx * (size_t)d->nfree);
        if (!d->free_idx) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        if ((s = lci_bin_read(b, fpos + b->marker, d->free_idx, 4 * (size_t)d->nfree, "the free-atom indices")) != LC_OK)
            return s;
        lci_bin_fix(b, d->free_idx, (size_t)d->nfree, 4);
        for (int64_t i = 0; i < d->nfree; i++) {
            if (d->free_idx[i] < 1 || d->free_idx[i] > d->natom)
                return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: free atom %lld is atom %d, expected 1 to %lld", path,
                                 (long long)(fpos + b->marker + 4 * i), (long long)i + 1, d->free_idx[i],
                                 (long long)d->natom);
            d->free_idx[i]--;
        }
    }
    int64_t m2 = 2 * b->marker;
    int64_t cellb = d->cell ? m2 + 48 : 0;
    d->first = off;
    d->frame0 = cellb + d->ncoord * (m2 + 4 * d->natom);
    d->frame = cellb + d->ncoord * (m2 + 4 * d->nfree);
    int64_t rest = b->size - d->first;
    if (rest < d->frame0) {
        d->nframes = 0;
        d->tail = rest;
    } else {
        d->nframes = 1 + (rest - d->frame0) / d->frame;
        d->tail = (rest - d->frame0) % d->frame;
    }
    return LC_OK;
}

static void dcd_close(dcd *d)
{
    lci_bin_close(&d->b);
    free(d->free_idx);
    d->free_idx = NULL;
}

/* Reads the coordinate records of the frame at off into xyz (n atoms, or the
 * free ones scattered through free_idx). buf holds n floats. */
static lc_status read_coords(dcd *d, int64_t k, int64_t off, int64_t n, const int32_t *idx, float *buf, float *xyz)
{
    lci_bin *b = &d->b;
    char what[96];
    int64_t len, next;
    lc_status s;
    if (d->cell) {
        snprintf(what, sizeof what, "the unit cell of frame %lld", (long long)k);
        if ((s = lci_bin_record(b, off, 48, what, &len, &next)) != LC_OK) return s;
        off = next;
    }
    for (int c = 0; c < d->ncoord; c++) {
        snprintf(what, sizeof what, "the %c coordinates of frame %lld", "XYZW"[c], (long long)k);
        if ((s = lci_bin_record(b, off, 4 * n, what, &len, &next)) != LC_OK) return s;
        if (c < 3) {
            if ((s = lci_bin_read(b, off + b->marker, buf, 4 * (size_t)n, what)) != LC_OK) return s;
            lci_bin_fix(b, buf, (size_t)n, 4);
            for (int64_t i = 0; i < n; i++) {
                if (!isfinite(buf[i]))
                    return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: atom %lld of frame %lld: %c = %g is not finite",
                                     b->path, (long long)(off + b->marker + 4 * i), (long long)(idx ? idx[i] : i) + 1,
                                     (long long)k, "xyz"[c], (double)buf[i]);
                xyz[3 * (idx ? idx[i] : i) + c] = buf[i];
            }
        }
        off = next;
    }
    return LC_OK;
}

static lc_status dcd_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    dcd d;
    lci_topo topo = {0};
    float *xyz = NULL, *buf = NULL;
    char why[4300] = "";
    lc_status s = header(dev, a->path, &d);
    int64_t k = a->desc->frame;
    if (s == LC_OK && d.nframes == 0)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: the file ends inside frame 0 (%lld bytes needed, %lld left)",
                      a->path, (long long)d.first, (long long)d.frame0, (long long)d.tail);
    if (s == LC_OK && k >= d.nframes)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld frame%s",
                      a->path, (long long)k, (long long)d.nframes, d.nframes == 1 ? "" : "s");
    if (s == LC_OK) s = lci_topo_load(dev, a, ".psf", &topo, why, sizeof why);
    if (s == LC_OK) {
        xyz = malloc(sizeof *xyz * 3 * (size_t)d.natom);
        buf = malloc(sizeof *buf * (size_t)d.natom);
        if (!xyz || !buf)
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %lld atoms", a->path, (long long)d.natom);
    }
    /* fixed atoms: their coordinates come from frame 0 */
    if (s == LC_OK) s = read_coords(&d, 0, d.first, d.natom, NULL, buf, xyz);
    if (s == LC_OK && k > 0) s = read_coords(&d, k, d.first + d.frame0 + (k - 1) * d.frame, d.nfree, d.free_idx, buf, xyz);
    dcd_close(&d);
    s = lci_topo_atoms(dev, a, s, &topo, why, xyz, s == LC_OK ? d.natom : 0, NULL, out);
    free(xyz);
    free(buf);
    lci_topo_free(&topo);
    return s;
}

static lc_status dcd_frames(lc_device *dev, const char *path, int64_t *out)
{
    dcd d;
    lc_status s = header(dev, path, &d);
    *out = s == LC_OK ? d.nframes : 0;
    if (s == LC_OK && d.tail)
        lci_log(dev, LC_LOG_WARNING, "%s: %lld bytes after frame %lld are not a whole frame (a run cut short?); ignored",
                path, (long long)d.tail, (long long)d.nframes - 1);
    dcd_close(&d);
    return s;
}

static int dcd_magic(const unsigned char *h, size_t n)
{
    return n >= 12 && ((!memcmp(h + 4, "CORD", 4) && ((h[0] == 84 && !h[1] && !h[2] && !h[3]) ||
                                                       (!h[0] && !h[1] && !h[2] && h[3] == 84))) ||
                       (!memcmp(h + 8, "CORD", 4) && (h[0] == 84 || h[7] == 84)));
}

const lci_format lci_format_dcd = {
    .name = "dcd", .kind = LC_KIND_PARTICLES, .extensions = ".dcd", .options = "radius radius_scale fields select value",
    .description = "CHARMM/NAMD/X-PLOR DCD trajectory (either byte order, unit cells, fixed atoms); elements from the "
                   "PSF topology (companion, or STEM.psf)",
    .magic = dcd_magic, .read = dcd_read, .frames = dcd_frames, .companion = 1};
