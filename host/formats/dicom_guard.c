/* The GDCM calls of the DICOM reader that run in the guard process
 * (guard.h), and the pixel reads around them. Debian's GDCM is built with
 * assertions and aborts on damaged input (fuzz_dicom's findings:
 * docs/FUZZING.md); lanecast's element walk (dicom_walk.c) stops what it
 * can predict, and what it cannot (GDCM's codecs, its fallback parsing
 * modes) runs in a forked child whose results come back through shared
 * memory. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include "host/formats/checked.h"
#include "host/formats/dicom.h"
#include "host/formats/guard.h"

#if LC_HAVE_GDCM

/* In a guard child: the fatal signals back to their default, so that a
 * fault in GDCM ends the child with its signal even where the host
 * (libFuzzer, a sanitizer) installed handlers that would exit it as if the
 * fault were the host's. */
static void child_signals(void)
{
    static const int fatal[] = {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL};
    for (size_t i = 0; i < sizeof fatal / sizeof fatal[0]; i++) signal(fatal[i], SIG_DFL);
}

/* The header of one file read in a guard child: the header (and its
 * per-frame arrays after it) come back through shared memory. */
typedef struct header_job {
    const char *path;
    unsigned char *shared; /* lci_dcm_meta, then frames x 6 doubles at most, then "read" */
} header_job;

#define HEADER_ROOM (sizeof(lci_dcm_meta) + (size_t)6 * 1000000 * sizeof(double) + 8)

static lc_status header_child(lc_device *dev, void *ctx)
{
    child_signals();
    const header_job *j = ctx;
    lci_dcm_meta m;
    char err[512];
    if (lci_gdcm_header(j->path, &m, err, sizeof err)) return lci_error(dev, LC_ERROR_FORMAT, "%s", err);
    size_t n = (size_t)m.frames, at = sizeof m;
    memcpy(j->shared, &m, sizeof m);
    double *arrays[3] = {m.frame_ipp, m.frame_offset, m.frame_rescale};
    const size_t len[3] = {3 * n, n, 2 * n};
    for (int i = 0; i < 3; i++)
        if (arrays[i]) memcpy(j->shared + at, arrays[i], len[i] * sizeof(double)), at += len[i] * sizeof(double);
    memcpy(j->shared + HEADER_ROOM - 8, "read", 5);
    lci_dcm_meta_free(&m);
    return LC_OK;
}

/* Where GDCM may read a file otherwise than the walk did (no syntax given,
 * elements without a VR in an explicit-VR data set: lci_dcm_pixel_el
 * ambiguous), its header is read in the guard process alone, with at most
 * 512 MB more address space: GDCM's fallback modes asserted on such files,
 * and one allocated (and cleared) 1.4 GB for a 322-byte file where a failed
 * allocation only had it try another mode. Other files are read here (a
 * fork costs up to ~20 ms). 1 when the guard ran (0 in *rc, *m filled; or
 * -1 with why in err), 0 when no child could run. */
int lci_dcm_header_guarded(lc_device *dev, const char *path, lci_dcm_meta *m, int *rc, char *err, size_t errlen)
{
    header_job j = {path, mmap(NULL, HEADER_ROOM, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0)};
    if (j.shared == MAP_FAILED) return 0;
    lc_status cs = LC_OK;
    char msg[LCI_MSG_MAX];
    int sig = lci_guarded(dev, "LANECAST_DICOM_GUARD", (uint64_t)512 << 20, header_child, &j, &cs, msg, sizeof msg);
    *rc = -1;
    if (sig == 0 && cs != LC_OK) snprintf(err, errlen, "%.400s", msg);
    else if (sig > 0)
        snprintf(err, errlen, "GDCM crashed reading its header (signal %d: %s) in lanecast's guard process: the file is "
                 "damaged", sig, strsignal(sig));
    else if (sig == 0 && memcmp(j.shared + HEADER_ROOM - 8, "read", 5))
        snprintf(err, errlen, "GDCM's header read in lanecast's guard process ended without finishing");
    else if (sig == 0) {
        memcpy(m, j.shared, sizeof *m);
        size_t n = (size_t)m->frames, at = sizeof *m;
        double **arrays[3] = {&m->frame_ipp, &m->frame_offset, &m->frame_rescale};
        const size_t len[3] = {3 * n, n, 2 * n};
        *rc = 0;
        for (int i = 0; i < 3; i++) {
            if (!*arrays[i]) continue; /* the child's pointer: only whether the array is there */
            if (!(*arrays[i] = malloc(len[i] * sizeof(double)))) *rc = -1;
            else memcpy(*arrays[i], j.shared + at, len[i] * sizeof(double));
            at += len[i] * sizeof(double);
        }
        if (*rc) lci_dcm_meta_free(m), snprintf(err, errlen, "out of memory");
    }
    munmap(j.shared, HEADER_ROOM);
    return sig >= 0;
}

/* Files decoded in one guard child at most: a fork of a process holding a
 * volume costs ~20 ms of system time (a child per file made an RLE series
 * of 300 slices take 8.3 s of system time instead of 1.7), and a batch's
 * output is copied once from the memory shared with the child. */
#define GUARD_BATCH_BYTES ((uint64_t)64 << 20)

/* Slices [k0, k1) of a volume, one file each and `unit` bytes (or, with
 * whole, the volume's one multi-frame file: k0 = 0, k1 = 1, `unit` its
 * bytes), decoded into dst. */
typedef struct px_job {
    const lci_dcm_input *in;
    const lci_dcm_volume *v;
    int k0, k1;
    uint64_t unit;
    unsigned char *dst;
} px_job;

/* Native pixel data the element walk placed is read here, not by GDCM:
 * its ImageReader asserts on headers it dislikes (a file whose Rescale
 * Slope it reads as 0: tests/fuzz_regress/dicom-rescale-assert), and the
 * bytes are a plain copy (words swapped for Explicit VR Big Endian).
 * Compressed and deflated data need GDCM's decoders. */
static int needs_gdcm(const lci_dcm_file *f) { return f->m.encapsulated || f->px.at < 0; }

/* Native words of f into dst (bytes of them; pixel_room checked that the
 * element holds them), little-endian. */
static lc_status native_read(lc_device *dev, const lci_dcm_file *f, unsigned char *dst, uint64_t bytes)
{
    FILE *in = fopen(f->path, "rb");
    int ok = in && fseeko(in, (off_t)f->px.value_at, SEEK_SET) == 0 && fread(dst, 1, (size_t)bytes, in) == bytes;
    if (in) fclose(in);
    if (!ok)
        return lci_error(dev, LC_ERROR_IO, "%s: cannot read the %llu bytes of pixel data at byte %lld", f->path,
                         (unsigned long long)bytes, (long long)f->px.value_at);
    int wb = f->m.bits_allocated / 8;
    if (wb > 1 && !strcmp(f->m.ts_uid, "1.2.840.10008.1.2.2"))
        for (uint64_t i = 0; i + (uint64_t)wb <= bytes; i += (uint64_t)wb)
            for (int a = 0, b = wb - 1; a < b; a++, b--) {
                unsigned char t = dst[i + (uint64_t)a];
                dst[i + (uint64_t)a] = dst[i + (uint64_t)b], dst[i + (uint64_t)b] = t;
            }
    return LC_OK;
}

static lc_status px_decode(lc_device *dev, void *ctx)
{
    const px_job *j = ctx;
    char err[512];
    for (int k = j->k0; k < j->k1; k++) {
        const lci_dcm_file *f = &j->in->files[j->v->slices[k].file];
        unsigned char *dst = j->dst + (uint64_t)(k - j->k0) * j->unit;
        if (!needs_gdcm(f)) {
            lc_status s = native_read(dev, f, dst, j->unit);
            if (s != LC_OK) return s;
        } else if (lci_gdcm_pixels(f->path, dst, (size_t)j->unit, err, sizeof err))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s", f->path, err);
    }
    return LC_OK;
}

/* The guard child's entry (child_signals); the mark after the
 * output tells a finished decode from a child that exited early. */
static const char done_mark[8] = "decoded";

static lc_status px_child(lc_device *dev, void *ctx)
{
    child_signals();
    const px_job *j = ctx;
    lc_status s = px_decode(dev, ctx);
    if (s == LC_OK) memcpy(j->dst + (uint64_t)(j->k1 - j->k0) * j->unit, done_mark, sizeof done_mark);
    return s;
}

/* Runs job; what GDCM decodes is decoded in the guard process (guard.h)
 * into memory shared with it, then copied to job->dst: Debian's GDCM is
 * built with assertions, and its codecs abort on damaged streams (a JPEG
 * fragment with a start-of-image marker and no frame header:
 * tests/fuzz_regress/dicom-jpeg-no-frame-header). */
static lc_status decode_job(lc_device *dev, px_job *job)
{
    int packed = 0;
    for (int k = job->k0; k < job->k1; k++) packed |= needs_gdcm(&job->in->files[job->v->slices[k].file]);
    uint64_t bytes = (uint64_t)(job->k1 - job->k0) * job->unit;
    size_t mapped = (size_t)bytes + sizeof done_mark;
    unsigned char *shared = packed ? mmap(NULL, mapped, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0)
                                   : MAP_FAILED;
    if (shared == MAP_FAILED) return px_decode(dev, job); /* all native, or no shared memory: unguarded */
    uint64_t lim = lci_memory_limit(dev), cap = 4 * bytes + ((uint64_t)512 << 20);
    for (int k = job->k0; k < job->k1; k++) {
        struct stat st;
        if (stat(job->in->files[job->v->slices[k].file].path, &st) == 0 && st.st_size >= 0) cap += 4 * (uint64_t)st.st_size;
    }
    lim = cap < lim ? cap : lim;
    lc_status cs = LC_OK;
    char msg[LCI_MSG_MAX];
    px_job child = *job;
    child.dst = shared;
    int sig = lci_guarded(dev, "LANECAST_DICOM_GUARD", lim, px_child, &child, &cs, msg, sizeof msg);
    int done = sig == 0 && cs == LC_OK && !memcmp(shared + bytes, done_mark, sizeof done_mark);
    if (done) memcpy(job->dst, shared, bytes);
    munmap(shared, mapped);
    const lci_dcm_file *f = &job->in->files[job->v->slices[job->k0].file];
    if (sig < 0) return px_decode(dev, job); /* no child could run (or LANECAST_DICOM_GUARD=0) */
    if (sig == 0 && cs != LC_OK) return lci_error(dev, cs, "%s", msg);
    if (sig == 0 && !done)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: GDCM's decode in lanecast's guard process ended without finishing "
                         "(transfer syntax %s)", f->path, f->m.ts_uid);
    if (sig == 0) return LC_OK;
    if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP)
        return lci_error(dev, LC_ERROR_IO, "%s: reading stopped by signal %d", f->path, sig);
    for (int k = job->k0; job->k1 - job->k0 > 1 && k < job->k1; k++) { /* which file: each alone */
        px_job one = {job->in, job->v, k, k + 1, job->unit, job->dst + (uint64_t)(k - job->k0) * job->unit};
        lc_status s = decode_job(dev, &one);
        if (s != LC_OK) return s;
    }
    return lci_error(dev, LC_ERROR_FORMAT,
                     "%s%s: GDCM crashed decoding the pixel data (transfer syntax %s; signal %d: %s) in lanecast's "
                     "guard process: the compressed data is damaged", f->path,
                     job->k1 - job->k0 > 1 ? " or one of the files after it in slice order" : "", f->m.ts_uid, sig,
                     strsignal(sig));
}

lc_status lci_dcm_decode(lc_device *dev, const lci_dcm_input *in, const lci_dcm_volume *v, unsigned char *raw)
{
    const lci_dcm_meta *m0 = v->first;
    uint64_t plane = (uint64_t)v->cols * (uint64_t)v->rows * (uint64_t)(m0->bits_allocated / 8);
    if (v->series->nfiles == 1) { /* one multi-frame file: frames to their sorted places */
        const lci_dcm_file *f = &in->files[v->slices[0].file];
        unsigned char *tmp = lci_alloc_checked(dev, f->path, (uint64_t)v->nslices, plane, 0, "stored voxels", 0);
        if (!tmp) return LC_ERROR_OUT_OF_MEMORY;
        px_job job = {in, v, 0, 1, plane * (uint64_t)v->nslices, tmp};
        lc_status s = decode_job(dev, &job);
        for (int k = 0; s == LC_OK && k < v->nslices; k++)
            memcpy(raw + (uint64_t)k * plane, tmp + (uint64_t)v->slices[k].frame * plane, plane);
        free(tmp);
        lci_load_progress(dev, 0.9);
        return s;
    }
    int per = plane >= GUARD_BATCH_BYTES ? 1 : (int)(GUARD_BATCH_BYTES / plane);
    for (int k = 0; k < v->nslices; k += per) {
        px_job job = {in, v, k, k + per < v->nslices ? k + per : v->nslices, plane, raw + (uint64_t)k * plane};
        lc_status s = decode_job(dev, &job);
        if (s != LC_OK) return s;
        lci_load_progress(dev, 0.9 * job.k1 / v->nslices);
    }
    return LC_OK;
}

#endif
