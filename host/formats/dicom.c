/* DICOM series (CT, MR, PET, ...) through GDCM (libgdcm-dev): a folder, a
 * list of files (option `files`, one per line) or one file of a series.
 * dicom_series.c finds the files, their series and a series' slice order
 * and geometry; GDCM decodes each file's pixel data (dicom_gdcm.cpp, any
 * transfer syntax GDCM decodes); this file turns the stored values into
 * voxels and hands them over as a grid.
 *
 * Values: each stored value keeps its Bits Stored low bits (sign-extended
 * when Pixel Representation is 1), then the file's Rescale Slope and
 * Intercept apply (CT: Hounsfield units; an enhanced multi-frame file's per
 * frame, from its functional groups). Without a rescale, uint8 and
 * uint16 stay as they are and int8/int16 become int16; with one, the values
 * are int16 (or uint16) when slope and intercept are integers and every
 * rescaled value fits, else float32. 32-bit values are read as float32.
 *
 * Orientation: the voxel-to-world matrix of the sorted slices goes onto the
 * nearest axis-aligned frame as NIfTI's does (orient.h): exact for axial,
 * coronal and sagittal stacks, a warning with the angle when oblique (voxel
 * sizes and the volume's centre kept), another when the slice positions lean
 * off the normal (gantry tilt: the stack is read unsheared). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/formats/dicom.h"
#include "host/formats/orient.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"

#if LC_HAVE_GDCM

/* Stored value i of a buffer of ba-bit little-endian words: its low bs bits,
 * sign-extended when sign (PS3.5 8.1.1: bits above High Bit may hold other
 * data and are dropped). */
static inline int64_t stored(const unsigned char *b, uint64_t i, int ba, int bs, int sign)
{
    uint64_t u = ba == 8    ? b[i]
                 : ba == 16 ? (uint64_t)b[2 * i] | (uint64_t)b[2 * i + 1] << 8
                            : (uint64_t)b[4 * i] | (uint64_t)b[4 * i + 1] << 8 | (uint64_t)b[4 * i + 2] << 16 |
                                  (uint64_t)b[4 * i + 3] << 24;
    u &= (1ull << bs) - 1;
    if (sign && (u >> (bs - 1) & 1)) return (int64_t)u - ((int64_t)1 << bs);
    return (int64_t)u;
}

static int is_int(double x) { return x == floor(x) && fabs(x) < 2147483648.0; }

/* The rescale of one slice: its frame's (enhanced multi-frame files give
 * one per frame) or its file's. */
static void rescale_of(const lci_dcm_input *in, const lci_dcm_slice *sl, double *slope, double *inter)
{
    const lci_dcm_meta *m = &in->files[sl->file].m;
    *slope = m->frame_rescale ? m->frame_rescale[2 * sl->frame] : m->slope;
    *inter = m->frame_rescale ? m->frame_rescale[2 * sl->frame + 1] : m->intercept;
}

/* The voxel type the values fit (see the top of the file); *as_is = 1 when
 * the stored words are those voxels already. */
static lc_value_type value_type(const lci_dcm_input *in, const lci_dcm_volume *v, const unsigned char *raw, int *as_is)
{
    const lci_dcm_meta *m0 = v->first;
    int ba = m0->bits_allocated, bs = m0->bits_stored, sign = m0->pixel_rep;
    int identity = 1, integral = 1;
    double slope, inter;
    for (int k = 0; k < v->nslices; k++) {
        rescale_of(in, &v->slices[k], &slope, &inter);
        identity &= slope == 1.0 && inter == 0.0;
        integral &= is_int(slope) && is_int(inter);
    }
    static const int little = 1;
    *as_is = identity && bs == ba && (ba == 16 || (ba == 8 && !sign)) && *(const char *)&little;
    if (ba == 32 || !integral) return LC_VALUE_FLOAT32;
    if (identity) return sign ? LC_VALUE_INT16 : ba == 8 ? LC_VALUE_UINT8 : LC_VALUE_UINT16;
    double lo = INFINITY, hi = -INFINITY;
    uint64_t plane = (uint64_t)v->cols * (uint64_t)v->rows;
    for (int k = 0; k < v->nslices; k++) {
        rescale_of(in, &v->slices[k], &slope, &inter);
        for (uint64_t i = 0; i < plane; i++) {
            double x = (double)stored(raw, (uint64_t)k * plane + i, ba, bs, sign) * slope + inter;
            lo = x < lo ? x : lo, hi = x > hi ? x : hi;
        }
    }
    if (lo >= -32768 && hi <= 32767) return LC_VALUE_INT16;
    if (lo >= 0 && hi <= 65535) return LC_VALUE_UINT16;
    return LC_VALUE_FLOAT32;
}

/* The voxels of type t from the stored values (rescaled per file); dst may
 * be raw itself when the widths agree (each word is read before it is
 * written). */
static lc_status convert(lc_device *dev, const lci_dcm_input *in, const lci_dcm_volume *v, const unsigned char *raw,
                         lc_value_type t, void *dst)
{
    const lci_dcm_meta *m0 = v->first;
    int ba = m0->bits_allocated, bs = m0->bits_stored, sign = m0->pixel_rep;
    uint64_t plane = (uint64_t)v->cols * (uint64_t)v->rows;
    for (int k = 0; k < v->nslices; k++) {
        const lci_dcm_file *f = &in->files[v->slices[k].file];
        double slope, inter;
        rescale_of(in, &v->slices[k], &slope, &inter);
        for (uint64_t i = k * plane, e = i + plane; i < e; i++) {
            int64_t s = stored(raw, i, ba, bs, sign);
            double x = (double)s * slope + inter;
            switch (t) {
            case LC_VALUE_UINT8: ((uint8_t *)dst)[i] = (uint8_t)s; break;
            case LC_VALUE_UINT16: ((uint16_t *)dst)[i] = (uint16_t)x; break;
            case LC_VALUE_INT16: ((int16_t *)dst)[i] = (int16_t)x; break;
            default:
                if (!(fabs(x) <= 3.4e38))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s: frame %d: value %g after rescale is not a finite float32",
                                     f->path, v->slices[k].frame, x);
                ((float *)dst)[i] = (float)x;
            }
        }
    }
    return LC_OK;
}

static lc_status dicom_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    if (s != LC_OK) return s;
    lci_dcm_input in;
    if ((s = lci_dcm_scan(dev, a, &in)) != LC_OK) return s;
    lci_dcm_volume v;
    int si = 0;
    memset(&v, 0, sizeof v);
    unsigned char *raw = NULL;
    void *vals = NULL, *data = NULL;
    lc_grid_desc *d = NULL;
    if ((s = lci_dcm_choose(dev, &in, a, &si)) != LC_OK || (s = lci_dcm_volume_of(dev, &in, si, &v)) != LC_OK) goto out;
    const lci_dcm_meta *m0 = v.first;
    uint64_t count = (uint64_t)v.cols * (uint64_t)v.rows * (uint64_t)v.nslices;
    if (!(raw = lci_alloc_checked(dev, a->path, count, (uint64_t)(m0->bits_allocated / 8), 64, "stored voxels", 0))) {
        s = LC_ERROR_OUT_OF_MEMORY;
        goto out;
    }
    if ((s = lci_dcm_decode(dev, &in, &v, raw)) != LC_OK) goto out;
    int as_is;
    lc_value_type t = value_type(&in, &v, raw, &as_is);
    int es = lci_value_size(t);
    if (as_is) vals = raw, raw = NULL;
    else if (es == m0->bits_allocated / 8 && t != LC_VALUE_FLOAT32) { /* same width (uint16 -> int16 HU): in place */
        if ((s = convert(dev, &in, &v, raw, t, raw)) != LC_OK) goto out;
        vals = raw, raw = NULL;
    } else {
        if (!(vals = lci_alloc_checked(dev, a->path, count, (uint64_t)es, 64, "voxels", 0))) {
            s = LC_ERROR_OUT_OF_MEMORY;
            goto out;
        }
        if ((s = convert(dev, &in, &v, raw, t, vals)) != LC_OK) goto out;
        free(raw), raw = NULL;
    }
    int64_t n[3] = {v.cols, v.rows, v.nslices};
    int perm[3], flip[3];
    double spacing[3], origin[3];
    double angle = lci_axis_frame((const double(*)[4])v.m, n, perm, flip, spacing, origin);
    if (angle > 0.0)
        lci_log(dev, LC_LOG_WARNING,
                "%s: the slices are oblique (up to %.2f degrees off the axes); lanecast grids are axis-aligned, so the "
                "nearest axis-aligned frame is used (voxel sizes and the volume's centre kept)", a->path, angle);
    if (v.shear > 0.5)
        lci_log(dev, LC_LOG_WARNING,
                "%s: the slice positions run %.2f degrees off the slice normal (gantry tilt?); the stack is read "
                "unsheared", a->path, v.shear);
    if (perm[0] == 0 && perm[1] == 1 && perm[2] == 2 && !flip[0] && !flip[1] && !flip[2]) data = vals, vals = NULL;
    else {
        if (!(data = lci_alloc_checked(dev, a->path, count, (uint64_t)es, 64, "voxels", 0))) {
            s = LC_ERROR_OUT_OF_MEMORY;
            goto out;
        }
        lci_axis_reorder(vals, data, es, n, perm, flip);
    }
    lci_log(dev, LC_LOG_INFO, "%s: series %d (%s, %s), %d x %d x %d, rescale %g, %g, read as %s", a->path, si + 1,
            v.series->uid, m0->modality, v.cols, v.rows, v.nslices, m0->slope, m0->intercept,
            t == LC_VALUE_UINT8 ? "uint8" : t == LC_VALUE_UINT16 ? "uint16" : t == LC_VALUE_INT16 ? "int16" : "float32");
    if (!(d = calloc(1, sizeof *d))) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
        goto out;
    }
    int64_t on[3] = {n[perm[0]], n[perm[1]], n[perm[2]]};
    s = lci_vol_hand_over(dev, a->path, d, on, t, spacing, origin, &o, data, out);
    data = NULL, d = NULL; /* out keeps them */
out:
    free(d);
    free(data);
    free(vals);
    free(raw);
    lci_dcm_volume_free(&v);
    lci_dcm_input_free(&in);
    return s;
}

/* lanecast info: every series of the input with its files, size, spacing,
 * modality, rescale and transfer syntax (or why it cannot be read). */
static lc_status dicom_describe(lc_device *dev, const lci_read_args *a, char *text, size_t size)
{
    lci_dcm_input in;
    lc_status s = lci_dcm_scan(dev, a, &in);
    if (s != LC_OK) return s;
    text[0] = 0;
#define ADD(...) snprintf(text + strlen(text), size - strlen(text), __VA_ARGS__)
    for (int i = 0; i < in.nseries; i++) {
        const lci_dcm_series *se = &in.series[i];
        const lci_dcm_meta *m = &in.files[se->files[0]].m;
        ADD("series %d%s  %s  %s%s%s%s, %d file%s\n", i + 1, in.chosen == i ? " (the file's)" : "",
            se->uid[0] ? se->uid : "(no Series Instance UID)", m->modality[0] ? m->modality : "?", m->description[0] ? " \"" : "",
            m->description, m->description[0] ? "\"" : "", se->nfiles, se->nfiles > 1 ? "s" : "");
        lci_dcm_volume v;
        char keep[LCI_MSG_MAX];
        snprintf(keep, sizeof keep, "%s", lc_last_error());
        if (lci_dcm_volume_of(NULL, &in, i, &v) != LC_OK) {
            ADD("  not readable: %s\n", lc_last_error());
            lci_error(NULL, LC_OK, "%s", keep);
            continue;
        }
        int varies = 0;
        for (int k = 0; k < v.nslices; k++) {
            double slope, inter;
            rescale_of(&in, &v.slices[k], &slope, &inter);
            varies |= slope != m->slope || inter != m->intercept;
        }
        ADD("  dims %d x %d x %d, spacing %g %g %g mm (columns, rows, slices), origin %g %g %g\n", v.cols, v.rows,
            v.nslices, m->spacing[1], m->spacing[0], v.step, v.m[0][3], v.m[1][3], v.m[2][3]);
        ADD("  %d-bit %s (%d stored), rescale slope %g intercept %g%s%s, syntax %s%s%s%s\n", m->bits_allocated,
            m->pixel_rep ? "signed" : "unsigned", m->bits_stored, m->slope, m->intercept,
            varies ? se->nfiles > 1 ? " (varies per file)" : " (varies per frame)" : "", !strcmp(m->modality, "CT") && m->have_rescale ? " (HU)" : "",
            m->ts_uid[0] ? m->ts_uid : "(none)", m->ts_name[0] ? " (" : "", m->ts_name, m->ts_name[0] ? ")" : "");
        lci_dcm_volume_free(&v);
    }
#undef ADD
    lci_dcm_input_free(&in);
    return LC_OK;
}
#define DICOM_READ dicom_read
#define DICOM_DESCRIBE dicom_describe
#else
#define DICOM_READ NULL
#define DICOM_DESCRIBE NULL
#endif

/* A Part 10 file: a 128-byte preamble, then "DICM" (PS3.10 7.1). */
static int dicom_magic(const unsigned char *h, size_t n) { return n >= 132 && !memcmp(h + 128, "DICM", 4); }

const lci_format lci_format_dicom = {
    .name = "dicom", .kind = LC_KIND_GRID, .extensions = ".dcm .dicom .ima", .options = "series files spacing origin",
    .description = "DICOM series (a folder, files, or one file of a series; CT, MR, ...): slices in order along the "
                   "normal, rescaled (CT: HU), oriented onto the nearest axis-aligned frame; series = N or UID",
    .magic = dicom_magic, .read = DICOM_READ, .package = "libgdcm-dev", .folders = 1, .describe = DICOM_DESCRIBE};
