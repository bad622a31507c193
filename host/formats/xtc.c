/* GROMACS XTC trajectories: frames of lossy-compressed coordinates in XDR
 * (big-endian 4-byte units). Each frame is
 *
 *   int magic 1995, int natoms, int step, float time, float box[3][3] (nm),
 *   int natoms again, then the coordinates:
 *     natoms <= 9: 3 * natoms floats (nm), uncompressed;
 *     else: float precision p, int minint[3], int maxint[3], int smallidx,
 *           int nbytes, nbytes of bit stream padded to a multiple of 4.
 *
 * The bit stream (the "xtc3" scheme, F. van Hoesel's xdr3dfcoord) codes the
 * coordinates as integers round(x * p) relative to minint. An atom is coded
 * "large": its three offsets from minint packed as one mixed-radix number of
 * sizeofints(maxint - minint + 1) bits (or, when a range exceeds 2^24, each
 * offset on its own in that range's bit length); then one bit says whether
 * the run length changes, and if so 5 bits give run + is_smaller + 1 (run a
 * multiple of 3, is_smaller in -1..1); then run / 3 "small" atoms follow,
 * each three offsets from the previous atom (biased by magicints[smallidx] / 2)
 * packed in smallidx bits with radix magicints[smallidx]; the first small
 * atom is stored before the large one (water: O after H1), and smallidx then
 * moves by is_smaller. The magic integers grow by 2^(1/3) so that three of
 * them fit smallidx bits. Bits are read most significant first; a packed
 * number's bytes arrive least significant first, the last one holding the
 * remaining (< 8) bits.
 *
 * Frames are found by reading their headers only (natoms and nbytes give
 * each frame's length), so lc_load_desc.frame seeks to frame k without
 * decoding frames 0..k-1. Coordinates become Angstrom (x10, as .gro). The
 * topology is a companion .gro, .pdb or .psf (topology.h). Errors name the
 * file, the byte and the frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/binfile.h"
#include "host/formats/checked.h"
#include "host/formats/topology.h"
#include "host/formats/xdr.h"

#define XTC_MAGIC 1995
#define XTC_MAX_ATOMS ((int64_t)INT32_MAX / 4)

static const int32_t magicints[] = {
    0,       0,       0,       0,       0,       0,       0,       0,       0,       8,       10,      12,
    16,      20,      25,      32,      40,      50,      64,      80,      101,     128,     161,     203,
    256,     322,     406,     512,     645,     812,     1024,    1290,    1625,    2048,    2580,    3250,
    4096,    5060,    6501,    8192,    10321,   13003,   16384,   20642,   26007,   32768,   41285,   52015,
    65536,   82570,   104031,  131072,  165140,  208063,  262144,  330280,  416127,  524287,  660561,  832255,
    1048576, 1321122, 1664510, 2097152, 2642245, 3329021, 4194304, 5284491, 6658042, 8388607, 10568983, 13316085,
    16777216};
#define FIRSTIDX 9
#define LASTIDX ((int)(sizeof magicints / sizeof magicints[0]))

typedef struct xtc_frame {
    int64_t off, next, data; /* the frame, the one after it, its coordinate data */
    int32_t natoms, step, smallidx;
    float time, box[9], precision;
    int32_t minint[3], maxint[3];
    uint32_t nbytes;
} xtc_frame;

/* The header of frame k at off. *eof = 1 when the file ends inside it (a
 * run cut short), the error then reported all the same. */
static lc_status frame_header(lci_bin *b, int64_t off, int64_t k, xtc_frame *f, int *eof)
{
    unsigned char h[92];
    char what[64];
    *eof = 0;
    memset(f, 0, sizeof *f);
    f->off = off;
    snprintf(what, sizeof what, "the header of frame %lld", (long long)k);
    int64_t left = b->size - off;
    if (left < 56) *eof = 1;
    lc_status s = lci_bin_read(b, off, h, 56, what);
    if (s != LC_OK) return s;
    int32_t magic = lci_bin_i32(b, h);
    if (magic != XTC_MAGIC)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: magic number %d, expected %d (an XTC frame)",
                         b->path, (long long)off, (long long)k, magic, XTC_MAGIC);
    f->natoms = lci_bin_i32(b, h + 4);
    f->step = lci_bin_i32(b, h + 8);
    f->time = lci_xdr_f32(h + 12);
    for (int i = 0; i < 9; i++) f->box[i] = lci_xdr_f32(h + 16 + 4 * i);
    int32_t n2 = lci_bin_i32(b, h + 52);
    if (f->natoms <= 0 || f->natoms > XTC_MAX_ATOMS)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: atom count %d, expected 1 to %lld", b->path,
                         (long long)off + 4, (long long)k, f->natoms, (long long)XTC_MAX_ATOMS);
    if (n2 != f->natoms)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: the coordinates say %d atoms, the header %d",
                         b->path, (long long)off + 52, (long long)k, n2, f->natoms);
    if (!isfinite(f->time))
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: time %g is not finite", b->path,
                         (long long)off + 12, (long long)k, (double)f->time);
    if (f->natoms <= 9) {
        f->data = off + 56;
        f->next = f->data + 12 * (int64_t)f->natoms;
        if (f->next > b->size) {
            *eof = 1;
            return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: the file ends inside frame %lld (%lld bytes needed, "
                             "%lld left)", b->path, (long long)f->data, (long long)k, 12LL * f->natoms,
                             (long long)(b->size - f->data));
        }
        return LC_OK;
    }
    if (left < 92) *eof = 1;
    if ((s = lci_bin_read(b, off + 56, h + 56, 36, what)) != LC_OK) return s;
    f->precision = lci_xdr_f32(h + 56);
    for (int c = 0; c < 3; c++) {
        f->minint[c] = lci_bin_i32(b, h + 60 + 4 * c);
        f->maxint[c] = lci_bin_i32(b, h + 72 + 4 * c);
    }
    f->smallidx = lci_bin_i32(b, h + 84);
    f->nbytes = (uint32_t)lci_bin_i32(b, h + 88);
    f->data = off + 92;
    if (!(f->precision > 0.0f) || !isfinite(f->precision))
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: precision %g, expected a positive number",
                         b->path, (long long)off + 56, (long long)k, (double)f->precision);
    for (int c = 0; c < 3; c++)
        if (f->minint[c] > f->maxint[c])
            return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: %c range %d to %d is empty", b->path,
                             (long long)off + 60 + 4 * c, (long long)k, "xyz"[c], f->minint[c], f->maxint[c]);
    if (f->smallidx < FIRSTIDX || f->smallidx >= LASTIDX)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: small-integer index %d, expected %d to %d",
                         b->path, (long long)off + 84, (long long)k, f->smallidx, FIRSTIDX, LASTIDX - 1);
    int64_t padded = ((int64_t)f->nbytes + 3) / 4 * 4;
    f->next = f->data + padded;
    if (f->nbytes > (uint32_t)INT32_MAX || f->next > b->size) {
        *eof = f->nbytes <= (uint32_t)INT32_MAX;
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: %u bytes of compressed coordinates, but "
                         "the file has %lld left", b->path, (long long)off + 88, (long long)k, f->nbytes,
                         (long long)(b->size - f->data));
    }
    return LC_OK;
}

/* Bits of the coordinate stream, most significant first. */
typedef struct bits {
    const unsigned char *p;
    uint64_t n, pos; /* bits in the stream, bits read */
} bits;

/* nb (0..32) bits from a window of the 5 bytes that hold them. */
static int get_bits(bits *r, int nb, uint32_t *out)
{
    if (r->pos + (uint64_t)nb > r->n) return -1;
    uint64_t byte = r->pos >> 3, nbytes = r->n >> 3, w = 0;
    int shift = (int)(r->pos & 7);
    for (uint64_t i = 0; i < 5; i++) w = w << 8 | (byte + i < nbytes ? r->p[byte + i] : 0u);
    *out = (uint32_t)((w >> (40 - shift - nb)) & ((1ull << nb) - 1));
    r->pos += (uint64_t)nb;
    return 0;
}

/* Three integers packed in nbits as one number of radix sizes[0..2] (the
 * first the most significant); -1 past the end or when the number does not
 * fit the radices (a damaged stream). */
static int get_ints(bits *r, int nbits, const uint32_t sizes[3], uint32_t out[3])
{
    unsigned char bytes[16] = {0};
    int nb = 0;
    uint32_t v;
    for (; nbits > 8; nbits -= 8) {
        if (get_bits(r, 8, &v)) return -1;
        bytes[nb++] = (unsigned char)v;
    }
    if (nbits > 0) {
        if (get_bits(r, nbits, &v)) return -1;
        bytes[nb++] = (unsigned char)v;
    }
    for (int i = 2; i > 0; i--) { /* long division of the little-endian bytes by sizes[i] */
        uint64_t rem = 0;
        for (int j = nb - 1; j >= 0; j--) {
            rem = rem << 8 | bytes[j];
            bytes[j] = (unsigned char)(rem / sizes[i]);
            rem %= sizes[i];
        }
        out[i] = (uint32_t)rem;
    }
    uint64_t q = 0;
    for (int j = nb - 1; j >= 0; j--) {
        if (q >> 32) return -1;
        q = q << 8 | bytes[j];
    }
    if (q >= sizes[0]) return -1;
    out[0] = (uint32_t)q;
    return 0;
}

/* Bits of the product of sizes[0..2] (xtc's sizeofints). */
static int bits_of_product(const uint32_t sizes[3])
{
    unsigned char bytes[32] = {1};
    int nb = 1;
    for (int i = 0; i < 3; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < nb; j++) {
            carry += (uint64_t)bytes[j] * sizes[i];
            bytes[j] = (unsigned char)(carry & 0xff);
            carry >>= 8;
        }
        for (; carry; carry >>= 8) bytes[nb++] = (unsigned char)(carry & 0xff);
    }
    int top = 0;
    while (top < 8 && (bytes[nb - 1] >> top)) top++;
    return (nb - 1) * 8 + top;
}

static int bits_of(uint64_t size)
{
    int n = 0;
    while (n < 32 && (1ull << n) <= size) n++;
    return n;
}

/* Decodes frame k's coordinates (nm) into xyz. */
static lc_status decode(lci_bin *b, const xtc_frame *f, int64_t k, float *xyz)
{
    int64_t n = f->natoms;
    if (n <= 9) {
        unsigned char raw[108];
        lc_status s = lci_bin_read(b, f->data, raw, (size_t)(12 * n), "the coordinates");
        if (s != LC_OK) return s;
        for (int64_t i = 0; i < 3 * n; i++) xyz[i] = lci_xdr_f32(raw + 4 * i);
        return LC_OK;
    }
    unsigned char *buf = lci_alloc_checked(b->dev, b->path, f->nbytes ? f->nbytes : 1, 1, 0, "compressed coordinates", 0);
    if (!buf) return LC_ERROR_OUT_OF_MEMORY;
    char what[64];
    snprintf(what, sizeof what, "the compressed coordinates of frame %lld", (long long)k);
    lc_status s = lci_bin_read(b, f->data, buf, f->nbytes, what);
    if (s != LC_OK) return free(buf), s;
    bits r = {buf, (uint64_t)f->nbytes * 8, 0};
    uint32_t size[3], bitsize[3] = {0, 0, 0};
    int large = 0;
    for (int c = 0; c < 3; c++) {
        uint64_t sz = (uint64_t)((int64_t)f->maxint[c] - f->minint[c] + 1);
        size[c] = (uint32_t)sz;
        if (sz > 0xffffff) large = 1;
    }
    /* a range of 2^32 (minint INT32_MIN, maxint INT32_MAX) cannot be a radix */
    for (int c = 0; c < 3; c++)
        if ((int64_t)f->maxint[c] - f->minint[c] + 1 > (int64_t)UINT32_MAX) large = -1;
    int nbits = 0;
    if (large > 0) for (int c = 0; c < 3; c++) bitsize[c] = (uint32_t)bits_of(size[c]);
    else if (large == 0) nbits = bits_of_product(size);
    int smallidx = f->smallidx;
    int smaller = magicints[smallidx - 1 > FIRSTIDX ? smallidx - 1 : FIRSTIDX] / 2;
    int smallnum = magicints[smallidx] / 2;
    const float inv = (float)(1.0 / (double)f->precision); /* as xdrfile: in double, then float */
    int64_t i = 0, run = 0, at = 0;
    const char *bad = NULL;
    while (i < n && !bad) {
        uint32_t u[3];
        int64_t cur[3], prev[3];
        if (large < 0) bad = "a coordinate range of 2^32";
        else if (large) {
            for (int c = 0; c < 3 && !bad; c++)
                if (get_bits(&r, (int)bitsize[c], &u[c]) || u[c] >= size[c]) bad = "a large atom outside its range";
        } else if (get_ints(&r, nbits, size, u)) {
            bad = "a large atom outside its range";
        }
        if (bad) break;
        for (int c = 0; c < 3; c++) prev[c] = (int64_t)f->minint[c] + u[c];
        i++;
        uint32_t flag, rl;
        int is_smaller = 0;
        if (get_bits(&r, 1, &flag)) {
            bad = "the run-length flag past the end of the stream";
            break;
        }
        if (flag) {
            if (get_bits(&r, 5, &rl)) {
                bad = "a run length past the end of the stream";
                break;
            }
            is_smaller = (int)(rl % 3);
            run = (int64_t)rl - is_smaller;
            is_smaller--;
        }
        if (run > 0) {
            if (i + run / 3 > n) {
                bad = "a run of small atoms past the atom count";
                break;
            }
            uint32_t ss[3] = {(uint32_t)magicints[smallidx], (uint32_t)magicints[smallidx], (uint32_t)magicints[smallidx]};
            for (int64_t j = 0; j < run && !bad; j += 3) {
                if (get_ints(&r, smallidx, ss, u)) {
                    bad = "a small atom outside its range";
                    break;
                }
                i++;
                for (int c = 0; c < 3; c++) cur[c] = prev[c] + (int64_t)u[c] - smallnum;
                if (j == 0) { /* the first small atom comes before the large one */
                    for (int c = 0; c < 3; c++) {
                        int64_t t = cur[c];
                        cur[c] = prev[c];
                        prev[c] = t;
                    }
                    for (int c = 0; c < 3; c++) xyz[3 * at + c] = (float)prev[c] * inv;
                    at++;
                } else {
                    memcpy(prev, cur, sizeof prev);
                }
                for (int c = 0; c < 3; c++) xyz[3 * at + c] = (float)cur[c] * inv;
                at++;
            }
        } else {
            for (int c = 0; c < 3; c++) xyz[3 * at + c] = (float)prev[c] * inv;
            at++;
        }
        smallidx += is_smaller;
        if (smallidx < FIRSTIDX || smallidx >= LASTIDX) {
            bad = "a small-integer index out of the table";
            break;
        }
        if (is_smaller < 0) {
            smallnum = smaller;
            smaller = smallidx > FIRSTIDX ? magicints[smallidx - 1] / 2 : 0;
        } else if (is_smaller > 0) {
            smaller = smallnum;
            smallnum = magicints[smallidx] / 2;
        }
    }
    free(buf);
    if (bad)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: frame %lld: damaged compressed coordinates: %s at atom "
                         "%lld (bit %llu of %llu)", b->path, (long long)(f->data + (int64_t)(r.pos / 8)), (long long)k,
                         bad, (long long)at + 1, (unsigned long long)r.pos, (unsigned long long)r.n);
    return LC_OK;
}

static lc_status xtc_open(lc_device *dev, const char *path, lci_bin *b)
{
    lc_status s = lci_bin_open(dev, path, "XTC trajectories", b);
    if (s == LC_OK) lci_xdr_order(b);
    return s;
}

/* frame_header as an lci_frame_header_fn */
static lc_status header_fn(lci_bin *b, int64_t off, int64_t k, void *frame, int64_t *next, int *eof)
{
    lc_status s = frame_header(b, off, k, frame, eof);
    *next = ((xtc_frame *)frame)->next;
    return s;
}

static lc_status xtc_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_bin b;
    lci_topo topo = {0};
    float *xyz = NULL;
    char why[4300] = "";
    xtc_frame f;
    lc_status s = xtc_open(dev, a->path, &b);
    if (s == LC_OK) s = lci_bin_seek_frame(&b, a->desc->frame, header_fn, &f);
    if (s == LC_OK) s = lci_topo_load(dev, a, ".gro .pdb .psf", &topo, why, sizeof why);
    if (s == LC_OK && !(xyz = lci_alloc_checked(dev, a->path, (uint64_t)f.natoms, 12, 0, "atoms", 0)))
        s = LC_ERROR_OUT_OF_MEMORY;
    if (s == LC_OK) s = decode(&b, &f, a->desc->frame, xyz);
    for (int64_t i = 0; s == LC_OK && i < 3 * (int64_t)f.natoms; i++) xyz[i] *= 10.0f; /* nm -> Angstrom */
    lci_bin_close(&b);
    s = lci_topo_atoms(dev, a, s, &topo, why, xyz, s == LC_OK ? f.natoms : 0, NULL, out);
    free(xyz);
    lci_topo_free(&topo);
    return s;
}

static lc_status xtc_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_bin b;
    xtc_frame f;
    *out = 0;
    lc_status s = xtc_open(dev, path, &b);
    if (s == LC_OK) s = lci_bin_count_frames(&b, header_fn, &f, "an XTC frame", out);
    lci_bin_close(&b);
    return s;
}

static int xtc_magic(const unsigned char *h, size_t n)
{
    /* magic 1995, a positive atom count repeated at byte 52 */
    return n >= 56 && !memcmp(h, "\0\0\x07\xcb", 4) && !memcmp(h + 4, h + 52, 4) && !(h[4] & 0x80);
}

const lci_format lci_format_xtc = {
    .name = "xtc", .kind = LC_KIND_PARTICLES, .extensions = ".xtc", .options = "radius radius_scale fields select value",
    .description = "GROMACS XTC trajectory (compressed, nm read as Angstrom); frames found by their headers; elements "
                   "from the topology (companion .gro/.pdb/.psf, or STEM.gro, STEM.pdb, STEM.psf)",
    .magic = xtc_magic, .read = xtc_read, .frames = xtc_frames, .companion = 1};
