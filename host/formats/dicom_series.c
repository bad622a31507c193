/* The files and series of a DICOM input, and one series as a volume
 * (dicom.h). Files are found by name (sorted, so that the series numbers
 * are the same on every run) but slices are ordered by their position along
 * the slice normal, never by name or Instance Number.
 *
 * Geometry (DICOM PS3.3 C.7.6.2.1.1): Image Orientation (Patient) gives the
 * directions of a row (the column index grows along it) and of a column;
 * Pixel Spacing is (between rows, between columns), so one column step is
 * the row direction times the second value. The slice normal is row x
 * column; each slice's Image Position (Patient) (its first voxel) dotted
 * with the normal orders the slices, and their differences are the slice
 * spacing. Enhanced multi-frame files give each frame's position in the
 * per-frame functional groups; other multi-frame files give the first
 * frame's and frame offsets along the normal (Grid Frame Offset Vector) or
 * Spacing Between Slices. Coordinates stay DICOM's patient frame (LPS, mm). */
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "host/formats/checked.h"
#include "host/formats/dicom.h"

#if LC_HAVE_GDCM

#define MAX_FILES 200000
/* Slice spacings may differ by this fraction of their mean (positions are
 * decimal strings, often rounded to 0.01 mm or coarser); a missing slice
 * differs by 100 %. */
#define SPACING_TOLERANCE 0.01

void lci_dcm_meta_free(lci_dcm_meta *m)
{
    free(m->frame_ipp), free(m->frame_offset), free(m->frame_rescale);
    m->frame_ipp = m->frame_offset = m->frame_rescale = NULL;
}

void lci_dcm_input_free(lci_dcm_input *in)
{
    for (int i = 0; i < in->nfiles; i++) free(in->files[i].path), lci_dcm_meta_free(&in->files[i].m);
    for (int i = 0; i < in->nseries; i++) free(in->series[i].files);
    free(in->files), free(in->series);
    memset(in, 0, sizeof *in);
}

/* Does the file carry the Part 10 preamble and "DICM" (PS3.10 7.1)? */
static int has_dicm(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned char b[132];
    int ok = f && fread(b, 1, sizeof b, f) == sizeof b && !memcmp(b + 128, "DICM", 4);
    if (f) fclose(f);
    return ok;
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The paths of the regular DICM files in folder dir, sorted; *n of them. */
static lc_status list_folder(lc_device *dev, const char *dir, char ***out, int *n)
{
    *out = NULL, *n = 0;
    DIR *d = opendir(dir);
    if (!d) return lci_error(dev, LC_ERROR_IO, "%s: cannot open the folder: %s", dir, strerror(errno));
    char **p = NULL;
    int cap = 0;
    lc_status s = LC_OK;
    for (struct dirent *e; s == LC_OK && (e = readdir(d));) {
        if (e->d_name[0] == '.') continue;
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        char *path = malloc(len);
        struct stat st;
        if (!path) {
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory listing the folder", dir);
            break;
        }
        snprintf(path, len, "%s%s%s", dir, dir[strlen(dir) - 1] == '/' ? "" : "/", e->d_name);
        if (stat(path, &st) || !S_ISREG(st.st_mode) || !has_dicm(path)) {
            free(path);
            continue;
        }
        if (*n == MAX_FILES) {
            free(path);
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: more than %d DICOM files in one folder", dir, MAX_FILES);
            break;
        }
        if (*n == cap) {
            char **q = realloc(p, sizeof *p * (size_t)(cap = cap ? 2 * cap : 64));
            if (!q) {
                free(path);
                s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory listing the folder", dir);
                break;
            }
            p = q;
        }
        p[(*n)++] = path;
    }
    closedir(d);
    if (s != LC_OK) {
        for (int i = 0; i < *n; i++) free(p[i]);
        free(p);
        *n = 0;
        return s;
    }
    if (*n) qsort(p, (size_t)*n, sizeof *p, by_name);
    *out = p;
    return LC_OK;
}

/* Adds path (taken over) with its header to in; *added = 0 when it holds no
 * image (a DICOMDIR, a report) or, with skip_bad, a header GDCM refuses. */
static lc_status add_file(lc_device *dev, lci_dcm_input *in, char *path, int skip_bad, int *added)
{
    *added = 0;
    lci_dcm_meta m;
    lci_dcm_pixel_el px;
    char err[512];
    int rc = lci_dcm_walk(path, &px, err, sizeof err);
    if (!rc && !(px.ambiguous && lci_dcm_header_guarded(dev, path, &m, &rc, err, sizeof err)))
        rc = lci_gdcm_header(path, &m, err, sizeof err);
    if (rc) {
        if (skip_bad) lci_log(dev, LC_LOG_WARNING, "%s: skipped: %s", path, err);
        lc_status s = skip_bad ? LC_OK : lci_error(dev, LC_ERROR_FORMAT, "%s: %s", path, err);
        free(path);
        return s;
    }
    if (m.rows == 0 || m.cols == 0) {
        lci_dcm_meta_free(&m);
        free(path);
        return LC_OK;
    }
    lci_dcm_file *f = realloc(in->files, sizeof *f * (size_t)(in->nfiles + 1));
    if (!f) {
        lci_dcm_meta_free(&m);
        free(path);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", in->where);
    }
    in->files = f;
    f[in->nfiles].path = path;
    f[in->nfiles].px = px;
    f[in->nfiles++].m = m;
    *added = 1;
    return LC_OK;
}

static lc_status group(lc_device *dev, lci_dcm_input *in)
{
    for (int i = 0; i < in->nfiles; i++) {
        const char *uid = in->files[i].m.series_uid;
        int s = 0;
        while (s < in->nseries && strcmp(in->series[s].uid, uid)) s++;
        if (s == in->nseries) {
            lci_dcm_series *q = realloc(in->series, sizeof *q * (size_t)(s + 1));
            if (!q) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", in->where);
            in->series = q;
            memset(&q[s], 0, sizeof q[s]);
            q[s].uid = uid;
            in->nseries++;
        }
        int *fl = realloc(in->series[s].files, sizeof *fl * (size_t)(in->series[s].nfiles + 1));
        if (!fl) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", in->where);
        in->series[s].files = fl;
        fl[in->series[s].nfiles++] = i;
    }
    return LC_OK;
}

static char *dup_str(const char *s, size_t n)
{
    char *p = malloc(n + 1);
    if (p) memcpy(p, s, n), p[n] = 0;
    return p;
}

lc_status lci_dcm_scan(lc_device *dev, const lci_read_args *a, lci_dcm_input *in)
{
    memset(in, 0, sizeof *in);
    in->where = a->path;
    in->chosen = -1;
    const lc_option *list = lci_option_find(a, "files");
    struct stat st;
    memset(&st, 0, sizeof st);
    lc_status s = LC_OK;
    int added;
    if (list) { /* exactly these files */
        for (const char *p = list->value; s == LC_OK && *p;) {
            const char *e = strchr(p, '\n');
            size_t len = e ? (size_t)(e - p) : strlen(p);
            if (len) {
                char *path = dup_str(p, len);
                if (!path) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
                else if (in->nfiles == MAX_FILES) {
                    free(path);
                    s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: more than %d files", a->path, MAX_FILES);
                } else if (stat(path, &st) || !S_ISREG(st.st_mode)) {
                    s = lci_error(dev, LC_ERROR_IO, "%s: not a readable regular file", path);
                    free(path);
                } else {
                    char keep[1024];
                    snprintf(keep, sizeof keep, "%s", path);
                    s = add_file(dev, in, path, 0, &added);
                    if (s == LC_OK && !added)
                        s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds no image (no Rows/Columns)", keep);
                }
            }
            p += len + (e ? 1 : 0);
        }
    } else if (stat(a->path, &st) == 0 && S_ISDIR(st.st_mode)) { /* a folder: every DICOM image in it */
        char **paths;
        int n;
        s = list_folder(dev, a->path, &paths, &n);
        for (int i = 0; i < n; i++) {
            if (s == LC_OK) s = add_file(dev, in, paths[i], 0, &added);
            else free(paths[i]);
        }
        free(paths);
    } else { /* one file: itself if it holds a volume, else its series in its folder */
        char *path = dup_str(a->path, strlen(a->path));
        if (!path) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
        s = add_file(dev, in, path, 0, &added);
        if (s == LC_OK && !added) s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds no image (no Rows/Columns)", a->path);
        if (s == LC_OK && in->files[0].m.frames == 1) {
            const char *slash = strrchr(a->path, '/');
            char *dir = slash ? dup_str(a->path, (size_t)(slash - a->path) + (slash == a->path)) : dup_str(".", 1);
            char **paths = NULL;
            int n = 0;
            if (!dir) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
            else s = list_folder(dev, dir, &paths, &n);
            struct stat self;
            stat(a->path, &self);
            for (int i = 0; i < n; i++) {
                struct stat o;
                int same = stat(paths[i], &o) == 0 && o.st_ino == self.st_ino && o.st_dev == self.st_dev;
                if (s != LC_OK || same) {
                    free(paths[i]);
                    continue;
                }
                s = add_file(dev, in, paths[i], 1, &added);
                if (s == LC_OK && added && strcmp(in->files[in->nfiles - 1].m.series_uid, in->files[0].m.series_uid)) {
                    in->nfiles--; /* another series */
                    free(in->files[in->nfiles].path);
                    lci_dcm_meta_free(&in->files[in->nfiles].m);
                }
            }
            free(paths);
            free(dir);
        }
        in->chosen = 0;
    }
    if (s == LC_OK && in->nfiles == 0)
        s = list || !S_ISDIR(st.st_mode)
                ? lci_error(dev, LC_ERROR_FORMAT, "%s: no DICOM images (files with a DICM preamble and Rows/Columns)",
                            a->path)
                : lci_error(dev, LC_ERROR_IO,
                            "%s: is a directory with no DICOM images (files with a DICM preamble and Rows/Columns), "
                            "the only files lanecast reads from a folder", a->path);
    if (s == LC_OK) s = group(dev, in);
    if (s != LC_OK) lci_dcm_input_free(in);
    return s;
}

lc_status lci_dcm_choose(lc_device *dev, const lci_dcm_input *in, const lci_read_args *a, int *out)
{
    const lc_option *o = lci_option_find(a, "series");
    if (!o) {
        if (in->nseries == 1 || in->chosen >= 0) return *out = in->chosen >= 0 ? in->chosen : 0, LC_OK;
        char list[1024] = "";
        for (int i = 0; i < in->nseries && strlen(list) < 900; i++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d: %s %s, %d file%s", i ? "; " : "", i + 1,
                     in->series[i].uid[0] ? in->series[i].uid : "(no UID)", in->files[in->series[i].files[0]].m.modality,
                     in->series[i].nfiles, in->series[i].nfiles > 1 ? "s" : "");
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: %d DICOM series (%s); choose one with --series N or --series UID (lanecast info lists them)",
                         a->path, in->nseries, list);
    }
    const char *v = o->value;
    char *end;
    long n = strtol(v, &end, 10);
    if (end != v && !*end && !strchr(v, '.')) {
        if (n < 1 || n > in->nseries)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: series %s: the input holds series 1 to %d", a->path, v,
                             in->nseries);
        return *out = (int)n - 1, LC_OK;
    }
    for (int i = 0; i < in->nseries; i++)
        if (!strcmp(in->series[i].uid, v)) return *out = i, LC_OK;
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                     "%s: series '%s': no series has this Series Instance UID (lanecast info lists the %d series)", a->path,
                     v, in->nseries);
}

void lci_dcm_volume_free(lci_dcm_volume *v)
{
    free(v->slices);
    memset(v, 0, sizeof *v);
}

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static int by_key(const void *a, const void *b)
{
    const lci_dcm_slice *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->file != y->file ? x->file - y->file : x->frame - y->frame;
}

/* Does the Pixel Data element hold the frames the header declares? Before
 * this check GDCM sized its image by Number of Frames x Rows x Columns and
 * zero-filled what the element lacked: a 464-byte file declaring 10^6
 * frames of 10 x 10 loaded as 200 MB of zeros, and a short element followed
 * by other data read as zeros (docs/FUZZING.md). Native data (read from the
 * element itself, dicom_guard.c) must hold every frame's bytes;
 * encapsulated data one fragment a frame at least (PS3.5 A.4: a fragment
 * holds one frame at most). A deflated data set is not walked (GDCM
 * inflates it). */
static lc_status pixel_room(lc_device *dev, const lci_dcm_file *f)
{
    const lci_dcm_meta *m = &f->m;
    const lci_dcm_pixel_el *px = &f->px;
    if (px->at == -2) return LC_OK;
    if (px->at < 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: no (7FE0,0010) Pixel Data element at the top level of the data set",
                         f->path);
    uint64_t need = (uint64_t)m->rows * (uint64_t)m->cols * (uint64_t)m->frames * (uint64_t)(m->bits_allocated / 8);
    if (m->encapsulated != (px->length < 0))
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: element (7FE0,0010) Pixel Data at byte %lld: %s, but transfer syntax %s is %s", f->path,
                         (long long)px->at, px->length < 0 ? "encapsulated (undefined length)" : "a defined length",
                         m->ts_uid[0] ? m->ts_uid : "(implicit VR little endian)",
                         m->encapsulated ? "encapsulated" : "native");
    if (px->length >= 0 && (uint64_t)px->length < need)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: element (7FE0,0010) Pixel Data at byte %lld holds %lld bytes, but (0028,0008) Number of "
                         "Frames %d x (0028,0010) Rows %d x (0028,0011) Columns %d x %d bytes ((0028,0100) Bits "
                         "Allocated %d) need %llu", f->path, (long long)px->at, (long long)px->length, m->frames,
                         m->rows, m->cols, m->bits_allocated / 8, m->bits_allocated, (unsigned long long)need);
    if (px->length < 0 && px->fragments < m->frames)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: element (7FE0,0010) Pixel Data at byte %lld holds %lld fragments after its offset table, "
                         "but (0028,0008) Number of Frames is %d (a fragment holds one frame at most)", f->path,
                         (long long)px->at, (long long)px->fragments, m->frames);
    return LC_OK;
}

/* What every file of a series must share with the first, and what lanecast
 * reads at all; the message names the file. */
static lc_status check_file(lc_device *dev, const lci_dcm_file *f, const lci_dcm_meta *m0)
{
    const lci_dcm_meta *m = &f->m;
    lc_status s;
    if (!m->ts_known)
        return lci_error(dev, LC_ERROR_UNSUPPORTED,
                         "%s: transfer syntax %s%s%s%s is not one GDCM %s decodes (convert it, e.g. gdcmconv --raw)",
                         f->path, m->ts_uid, m->ts_name[0] ? " (" : "", m->ts_name, m->ts_name[0] ? ")" : "",
                         lci_gdcm_version());
    if (m->samples != 1 || (m->photometric[0] && strncmp(m->photometric, "MONOCHROME", 10)))
        return lci_error(dev, LC_ERROR_UNSUPPORTED,
                         "%s: %s pixels (%d samples per pixel) are not read: lanecast volumes hold one value a voxel "
                         "(MONOCHROME1/2)", f->path, m->photometric[0] ? m->photometric : "colour", m->samples);
    if (m->bits_allocated != 8 && m->bits_allocated != 16 && m->bits_allocated != 32)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: (0028,0100) Bits Allocated is %d; lanecast reads 8, 16 and 32",
                         f->path, m->bits_allocated);
    if (m->bits_stored < 1 || m->bits_stored > m->bits_allocated || m->high_bit != m->bits_stored - 1)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: (0028,0101) Bits Stored %d and (0028,0102) High Bit %d do not fit Bits Allocated %d "
                         "(lanecast reads High Bit = Bits Stored - 1)", f->path, m->bits_stored, m->high_bit,
                         m->bits_allocated);
    if (m->pixel_rep > 1)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: (0028,0103) Pixel Representation is %d, expected 0 or 1", f->path,
                         m->pixel_rep);
    if (m->rows < 2 || m->cols < 2)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %d x %d pixels: lanecast grids need 2 or more along each axis",
                         f->path, m->cols, m->rows);
    if (!(m->slope != 0.0 && isfinite(m->slope) && isfinite(m->intercept)))
        return lci_error(dev, LC_ERROR_FORMAT, "%s: (0028,1053) Rescale Slope %g is not a finite non-zero number",
                         f->path, m->slope);
    if ((s = pixel_room(dev, f)) != LC_OK) return s;
    if (m == m0) return LC_OK;
    if (m->rows != m0->rows || m->cols != m0->cols)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %d x %d pixels (columns x rows), but the series' first file has %d x %d",
                         f->path, m->cols, m->rows, m0->cols, m0->rows);
    if (m->bits_allocated != m0->bits_allocated || m->bits_stored != m0->bits_stored || m->pixel_rep != m0->pixel_rep)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: %d bits stored in %d, %s, but the series' first file has %d in %d, %s", f->path,
                         m->bits_stored, m->bits_allocated, m->pixel_rep ? "signed" : "unsigned", m0->bits_stored,
                         m0->bits_allocated, m0->pixel_rep ? "signed" : "unsigned");
    for (int i = 0; i < 6; i++)
        if (fabs(m->iop[i] - m0->iop[i]) > 1e-4)
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: (0020,0037) Image Orientation (Patient) differs from the series' first file's", f->path);
    for (int i = 0; i < 2; i++)
        if (fabs(m->spacing[i] - m0->spacing[i]) > 1e-4 * m0->spacing[i])
            return lci_error(dev, LC_ERROR_FORMAT, "%s: (0028,0030) Pixel Spacing %g\\%g differs from the first file's %g\\%g",
                             f->path, m->spacing[0], m->spacing[1], m0->spacing[0], m0->spacing[1]);
    return LC_OK;
}

/* The slices of a multi-frame file (the series' only file). */
static lc_status frame_positions(lc_device *dev, const lci_dcm_file *f, int file, const double n[3], lci_dcm_slice *sl)
{
    const lci_dcm_meta *m = &f->m;
    for (int k = 0; k < m->frames; k++) {
        sl[k].file = file, sl[k].frame = k;
        if (m->frame_ipp) {
            memcpy(sl[k].pos, m->frame_ipp + 3 * k, sizeof sl[k].pos);
            continue;
        }
        double off = m->frame_offset ? m->frame_offset[k] : m->have_between ? k * m->between : NAN;
        if (!isfinite(off))
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: %d frames but no frame positions: neither per-frame Plane Position (0020,9113), Grid "
                             "Frame Offset Vector (3004,000C) nor Spacing Between Slices (0018,0088)", f->path, m->frames);
        for (int c = 0; c < 3; c++) sl[k].pos[c] = m->ipp[c] + off * n[c];
    }
    return LC_OK;
}

/* "FILE" or "FILE (frame F)" for slices of multi-frame files. */
static const char *slice_name(const lci_dcm_input *in, const lci_dcm_slice *sl, char *buf, size_t n)
{
    const lci_dcm_file *f = &in->files[sl->file];
    if (f->m.frames > 1) snprintf(buf, n, "%s (frame %d)", f->path, sl->frame);
    else snprintf(buf, n, "%s", f->path);
    return buf;
}

/* Uneven spacing: the message gives each distinct spacing with its count
 * and the first pair of slices whose spacing is not the most common one. */
static lc_status uneven(lc_device *dev, const lci_dcm_input *in, const lci_dcm_volume *v)
{
    double seen[6];
    int count[6], ns = 0, more = 0, mode = 0;
    for (int i = 0; i + 1 < v->nslices; i++) {
        double d = v->slices[i + 1].key - v->slices[i].key;
        int j = 0;
        while (j < ns && fabs(seen[j] - d) > SPACING_TOLERANCE * seen[j]) j++;
        if (j < ns) count[j]++;
        else if (ns < 6) seen[ns] = d, count[ns++] = 1;
        else more = 1;
    }
    char list[400] = "";
    for (int j = 0; j < ns; j++) {
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%g mm x %d", j ? ", " : "", seen[j], count[j]);
        if (count[j] > count[mode]) mode = j;
    }
    int bad = 0;
    while (bad + 2 < v->nslices &&
           fabs(v->slices[bad + 1].key - v->slices[bad].key - seen[mode]) <= SPACING_TOLERANCE * seen[mode])
        bad++;
    char an[1100], bn[1100];
    return lci_error(dev, LC_ERROR_FORMAT,
                     "%s: uneven slice spacing along the slice normal: %g mm between %s and %s, spacings %s%s; "
                     "lanecast grids are evenly spaced (missing slices, or two stacks in one series?)",
                     in->where, v->slices[bad + 1].key - v->slices[bad].key,
                     slice_name(in, &v->slices[bad], an, sizeof an), slice_name(in, &v->slices[bad + 1], bn, sizeof bn),
                     list, more ? ", ..." : "");
}

lc_status lci_dcm_volume_of(lc_device *dev, const lci_dcm_input *in, int si, lci_dcm_volume *v)
{
    memset(v, 0, sizeof *v);
    const lci_dcm_series *se = &in->series[si];
    const lci_dcm_file *f0 = &in->files[se->files[0]];
    const lci_dcm_meta *m0 = &f0->m;
    v->series = se, v->first = m0, v->cols = m0->cols, v->rows = m0->rows;
    lc_status s = LC_OK;
    for (int i = 0; i < se->nfiles && s == LC_OK; i++) s = check_file(dev, &in->files[se->files[i]], m0);
    if (s != LC_OK) return s;
    for (int i = 0; i < se->nfiles; i++) {
        const lci_dcm_file *f = &in->files[se->files[i]];
        if (f->m.frames > 1 && se->nfiles > 1)
            return lci_error(dev, LC_ERROR_UNSUPPORTED,
                             "%s: a multi-frame file (%d frames) in a series of %d files: lanecast reads a multi-frame "
                             "file alone (name it, or --series)", f->path, f->m.frames, se->nfiles);
        if (!f->m.have_ipp)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: no (0020,0032) Image Position (Patient): the slice cannot be placed",
                             f->path);
        if (!f->m.have_iop)
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: no (0020,0037) Image Orientation (Patient): the slice normal is unknown", f->path);
    }
    const double *r = m0->iop, *c = m0->iop + 3;
    double n[3] = {r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2], r[0] * c[1] - r[1] * c[0]};
    double nn = sqrt(dot(n, n));
    if (fabs(sqrt(dot(r, r)) - 1.0) > 1e-3 || fabs(sqrt(dot(c, c)) - 1.0) > 1e-3 || fabs(dot(r, c)) > 1e-3 || !(nn > 0.5))
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: (0020,0037) Image Orientation (Patient) %g\\%g\\%g\\%g\\%g\\%g is not two orthogonal unit "
                         "vectors", f0->path, r[0], r[1], r[2], c[0], c[1], c[2]);
    for (int k = 0; k < 3; k++) n[k] /= nn;
    double sp[2] = {1.0, 1.0};
    if (m0->have_spacing) sp[0] = m0->spacing[0], sp[1] = m0->spacing[1];
    else lci_log(dev, LC_LOG_WARNING, "%s: no (0028,0030) Pixel Spacing: 1 mm assumed", f0->path);
    if (!(sp[0] > 0 && sp[1] > 0))
        return lci_error(dev, LC_ERROR_FORMAT, "%s: (0028,0030) Pixel Spacing %g\\%g is not positive", f0->path, sp[0],
                         sp[1]);
    v->nslices = se->nfiles > 1 ? se->nfiles : m0->frames;
    if (v->nslices < 2)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: one slice (%d x %d): lanecast grids need 2 or more slices (give the folder or the other "
                         "files of the series)", f0->path, m0->cols, m0->rows);
    if ((double)v->cols * v->rows * v->nslices > 2147483583.0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %d x %d x %d voxels, more than a grid holds (2^31 - 65)",
                         in->where, v->cols, v->rows, v->nslices);
    if (!(v->slices = calloc((size_t)v->nslices, sizeof *v->slices)))
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", in->where);
    if (se->nfiles > 1)
        for (int i = 0; i < se->nfiles; i++) {
            v->slices[i].file = se->files[i];
            memcpy(v->slices[i].pos, in->files[se->files[i]].m.ipp, sizeof v->slices[i].pos);
        }
    else if ((s = frame_positions(dev, f0, se->files[0], n, v->slices)) != LC_OK)
        return lci_dcm_volume_free(v), s;
    for (int i = 0; i < v->nslices; i++) v->slices[i].key = dot(v->slices[i].pos, n);
    qsort(v->slices, (size_t)v->nslices, sizeof *v->slices, by_key);
    v->step = (v->slices[v->nslices - 1].key - v->slices[0].key) / (v->nslices - 1);
    for (int i = 0; i + 1 < v->nslices; i++) {
        const lci_dcm_slice *a = &v->slices[i], *b = &v->slices[i + 1];
        if (b->key - a->key <= 1e-6 * (fabs(a->key) + 1.0)) {
            char an[1100], bn[1100];
            s = lci_error(dev, LC_ERROR_FORMAT,
                          "%s and %s lie at the same position along the slice normal (%g mm): two stacks in one series?",
                          slice_name(in, a, an, sizeof an), slice_name(in, b, bn, sizeof bn), a->key);
            return lci_dcm_volume_free(v), s;
        }
    }
    for (int i = 0; i + 1 < v->nslices; i++)
        if (fabs(v->slices[i + 1].key - v->slices[i].key - v->step) > SPACING_TOLERANCE * v->step) {
            s = uneven(dev, in, v);
            return lci_dcm_volume_free(v), s;
        }
    /* how far the line of slice positions leans off the normal */
    const double *p0 = v->slices[0].pos, *p1 = v->slices[v->nslices - 1].pos;
    double d[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    double along = dot(d, n), off = sqrt(fmax(0.0, dot(d, d) - along * along));
    v->shear = atan2(off, fabs(along)) * 180.0 / M_PI;
    for (int k = 0; k < 3; k++) {
        v->m[k][0] = r[k] * sp[1];
        v->m[k][1] = c[k] * sp[0];
        v->m[k][2] = n[k] * v->step;
        v->m[k][3] = p0[k];
    }
    return LC_OK;
}

#endif
