/* A walk over every element header of a DICOM file before GDCM reads it
 * (dicom_gdcm.h, lci_dcm_walk). Debian's GDCM is built with assertions and
 * trusts declared lengths: a file that ends inside a File Meta Information
 * element aborts the process, and an element declaring 4 GB in a 500-byte
 * file has GDCM allocate and clear 4 GB before its read fails. Here every
 * declared length is checked against what holds it (the file, the
 * enclosing sequence or item), sequences and items are walked down to their
 * delimiters, and encapsulated pixel data down to its fragments; values are
 * skipped, never read. The walk stops at the first element it cannot place
 * and names it with its byte offset, and notes where the top-level Pixel
 * Data element is and what it declares (its length, or its fragments), so
 * that frame counts can be held against it before GDCM sizes a buffer by
 * them (dicom_series.c). */
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "host/formats/dicom.h"

#define MAX_DEPTH 32

typedef struct walker {
    FILE *f;
    int64_t size;
    int expl, big; /* the data set's syntax */
    lci_dcm_pixel_el *px; /* the top-level Pixel Data element, as found */
    char *err;
    size_t errlen;
} walker;

static int fail(walker *w, int64_t at, unsigned g, unsigned e, const char *what)
{
    snprintf(w->err, w->errlen, "element (%04X,%04X) at byte %lld: %s", g, e, (long long)at, what);
    return -1;
}

static int get(walker *w, int64_t at, unsigned char *b, size_t n)
{
    return fseeko(w->f, (off_t)at, SEEK_SET) == 0 && fread(b, 1, n, w->f) == n ? 0 : -1;
}

static unsigned u16(const unsigned char *b, int big) { return big ? (unsigned)b[0] << 8 | b[1] : (unsigned)b[1] << 8 | b[0]; }

static uint32_t u32(const unsigned char *b, int big)
{
    return big ? (uint32_t)u16(b, 1) << 16 | u16(b + 2, 1) : (uint32_t)u16(b + 2, 0) << 16 | u16(b, 0);
}

/* The VRs of PS3.5 6.2; *wide: a 32-bit length after two reserved bytes. */
static int known_vr(const unsigned char *v, int *wide)
{
    static const char vrs[] = "AE AS AT CS DA DS DT FD FL IS LO LT OB OD OF OL OV OW PN SH SL SQ SS ST SV TM UC UI UL "
                              "UN UR US UT UV";
    static const char wides[] = "OB OD OF OL OV OW SQ SV UC UN UR UT UV";
    char s[3] = {(char)v[0], (char)v[1], 0};
    if (v[0] < 'A' || v[0] > 'Z' || v[1] < 'A' || v[1] > 'Z' || !strstr(vrs, s)) return 0;
    *wide = strstr(wides, s) != NULL;
    return 1;
}

static int data_set(walker *w, int64_t p, int64_t end, int depth, int64_t *stop);

/* The items of a sequence (or the fragments of encapsulated pixel data,
 * raw = 1) from p: up to end when the length is defined, else to the
 * sequence delimiter; *stop: just past it; *count: how many (NULL: not
 * counted). */
static int items(walker *w, int64_t p, int64_t end, int undefined, int raw, int depth, int64_t *stop,
                 int64_t *count)
{
    unsigned char h[8];
    for (int64_t n = 0;; n++) {
        if (count) *count = n;
        if (!undefined && p == end) return *stop = p, 0;
        if (p + 8 > end) return fail(w, p, 0xFFFE, 0xE000, "the sequence ends inside an item's header");
        if (get(w, p, h, 8)) return fail(w, p, 0xFFFE, 0xE000, "cannot read the item's header");
        unsigned g = u16(h, w->big), e = u16(h + 2, w->big);
        uint32_t len = u32(h + 4, w->big);
        if (g == 0xFFFE && e == 0xE0DD && undefined) return *stop = p + 8, 0;
        if (g != 0xFFFE || e != 0xE000) return fail(w, p, g, e, "an element where a sequence item should be");
        int64_t q = p + 8;
        if (len == 0xFFFFFFFFu) {
            if (raw) return fail(w, p, g, e, "a pixel data fragment of undefined length");
            if (data_set(w, q, end, depth + 1, &p)) return -1;
            continue;
        }
        if (q + (int64_t)len > end)
            return fail(w, p, g, e, "the item's length runs past the end of its sequence or the file");
        if (!raw && data_set(w, q, q + len, depth + 1, NULL)) return -1;
        p = q + len;
    }
}

/* The elements from p to end (defined length), or, for an item of
 * undefined length (stop != NULL), to its item delimiter (*stop: just past
 * it), which must come before end: GDCM asserts on an item that its
 * sequence or the file ends first
 * (tests/fuzz_regress/dicom-item-no-delimiter). */
static int data_set(walker *w, int64_t p, int64_t end, int depth, int64_t *stop)
{
    unsigned char h[12];
    if (depth > MAX_DEPTH) return fail(w, p, 0, 0, "sequences nested more than 32 deep");
    while (p < end) {
        int64_t at = p;
        if (p + 8 > end) return fail(w, p, 0, 0, "the file or its item ends inside an element's header");
        if (get(w, p, h, 8)) return fail(w, p, 0, 0, "cannot read the element's header");
        unsigned g = u16(h, w->big), e = u16(h + 2, w->big);
        if (g == 0xFFFE) { /* delimiters carry a 4-byte length in every syntax */
            if (e == 0xE00D && stop) return *stop = p + 8, 0;
            return fail(w, p, g, e, "a delimiter or item outside a sequence");
        }
        int wide = 0, sq = 0;
        int64_t q;
        uint32_t len;
        if (w->expl && known_vr(h + 4, &wide)) {
            sq = h[4] == 'S' && h[5] == 'Q';
            if (wide) {
                if (p + 12 > end) return fail(w, p, g, e, "the file or its item ends inside the element's header");
                if (get(w, p, h, 12)) return fail(w, p, g, e, "cannot read the element's header");
                len = u32(h + 8, w->big), q = p + 12;
            } else
                len = u16(h + 6, w->big), q = p + 8;
        } else { /* implicit VR (or an explicit file's implicit element, which GDCM reads so) */
            if (w->expl) w->px->ambiguous = 1;
            len = u32(h + 4, w->big), q = p + 8;
            sq = -1; /* unknown: a sequence when undefined */
        }
        if (len == 0xFFFFFFFFu) {
            int un = w->expl && h[4] == 'U' && h[5] == 'N';
            int pixels = g == 0x7FE0 && e == 0x0010;
            if (!(sq || un || pixels || (w->expl && h[4] == 'O')))
                return fail(w, p, g, e, "an undefined length on an element that is not a sequence");
            int64_t n = 0;
            if (items(w, q, end, 1, pixels, depth, &p, &n)) return -1;
            /* the first item is the Basic Offset Table (PS3.5 A.4) */
            if (pixels && depth == 0) {
                w->px->at = at, w->px->value_at = q, w->px->length = -1;
                w->px->fragments = n > 0 ? n - 1 : 0;
            }
            continue;
        }
        if (q + (int64_t)len > end)
            return fail(w, p, g, e, "its value's length runs past the end of the file or of its item");
        if (sq == 1 && items(w, q, q + len, 0, 0, depth, &p, NULL)) return -1;
        if (g == 0x7FE0 && e == 0x0010 && depth == 0)
            w->px->at = at, w->px->value_at = q, w->px->length = len, w->px->fragments = 0;
        p = q + len;
    }
    if (stop) return fail(w, p, 0xFFFE, 0xE00D, "an item of undefined length ends with its sequence or the file, "
                                                 "before its item delimiter");
    return 0;
}

int lci_dcm_walk(const char *path, lci_dcm_pixel_el *px, char *err, size_t errlen)
{
    *px = (lci_dcm_pixel_el){-1, -1, -1, 0, 0};
    walker w = {fopen(path, "rb"), 0, 1, 0, px, err, errlen};
    struct stat st;
    if (!w.f || fstat(fileno(w.f), &st)) {
        if (w.f) fclose(w.f);
        snprintf(err, errlen, "cannot open the file");
        return -1;
    }
    w.size = (int64_t)st.st_size;
    unsigned char h[12];
    int64_t p = w.size >= 132 && !get(&w, 128, h, 4) && !memcmp(h, "DICM", 4) ? 132 : 0;
    char ts[72] = "";
    int rc = 0;
    /* File Meta Information: group 0002, explicit VR little endian (PS3.10
     * 7.1); a file without the preamble may lack it or have it implicit */
    int meta_expl = 1;
    if (p == 0 && !get(&w, 0, h, 6) && u16(h, 0) == 2) {
        int wide;
        meta_expl = known_vr(h + 4, &wide);
    }
    for (int first = 1;; first = 0) {
        if (p + 4 > w.size) {
            snprintf(err, errlen, "the file ends at byte %lld, %s", (long long)w.size,
                     first ? "before its first element" : "after the File Meta Information, with no data set");
            rc = -1;
            break;
        }
        if (get(&w, p, h, 4) || u16(h, 0) != 2) break;
        unsigned e = u16(h + 2, 0);
        int wide = 0;
        int64_t q;
        uint32_t len;
        if (p + 8 > w.size || get(&w, p, h, 8)) {
            rc = fail(&w, p, 2, e, "the file ends inside the File Meta Information element");
            break;
        }
        if (meta_expl) {
            if (!known_vr(h + 4, &wide)) {
                rc = fail(&w, p, 2, e, "not a DICOM VR in the File Meta Information (explicit VR little endian)");
                break;
            }
            if (h[4] == 'S' && h[5] == 'Q') {
                rc = fail(&w, p, 2, e, "a sequence in the File Meta Information");
                break;
            }
            if (wide && (p + 12 > w.size || get(&w, p, h, 12))) {
                rc = fail(&w, p, 2, e, "the file ends inside the File Meta Information element");
                break;
            }
            len = wide ? u32(h + 8, 0) : u16(h + 6, 0), q = p + (wide ? 12 : 8);
        } else
            len = u32(h + 4, 0), q = p + 8;
        if (len == 0xFFFFFFFFu || q + (int64_t)len > w.size) {
            rc = fail(&w, p, 2, e, len == 0xFFFFFFFFu ? "an undefined length in the File Meta Information"
                                                       : "its value's length runs past the end of the file");
            break;
        }
        if (e == 0x0010 && len < sizeof ts && !get(&w, q, (unsigned char *)ts, len)) {
            ts[len] = 0;
            for (size_t k = len; k > 0 && (ts[k - 1] == ' ' || ts[k - 1] == 0); k--) ts[k - 1] = 0;
        }
        p = q + len;
    }
    /* the data set, in its syntax; a deflated one is GDCM's to inflate */
    if (rc == 0 && !strcmp(ts, "1.2.840.10008.1.2.1.99")) px->at = -2;
    else if (rc == 0) {
        w.expl = strcmp(ts, "1.2.840.10008.1.2") != 0 && (ts[0] || meta_expl);
        w.big = !strcmp(ts, "1.2.840.10008.1.2.2");
        if (!ts[0] && p + 6 <= w.size && !get(&w, p, h, 6)) { /* no meta header: as the first element looks */
            int wide;
            w.expl = known_vr(h + 4, &wide);
        }
        if (!ts[0]) px->ambiguous = 1; /* GDCM guesses the syntax its own way */
        rc = data_set(&w, p, w.size, 0, NULL);
    }
    fclose(w.f);
    return rc;
}
