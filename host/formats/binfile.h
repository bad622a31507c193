/* Binary particle files (DCD, GADGET): a plain file with its size known up
 * front, the byte order it was written in, and Fortran unformatted records
 * (a length marker, the data, the same marker again) checked as they are
 * read. Every error names the file and the byte offset. Sizes are checked
 * against the file's size before anything is allocated. */
#ifndef LC_HOST_BINFILE_H
#define LC_HOST_BINFILE_H

#include <stdint.h>
#include <stdio.h>
#include "host/internal.h"

typedef struct lci_bin {
    lc_device *dev;
    const char *path;
    FILE *f;
    int64_t size;  /* bytes in the file */
    int swap;      /* 1: the file's byte order is not ours */
    int marker;    /* bytes of a record marker: 4 (usual) or 8 */
} lci_bin;

/* Opens a plain file; a gzip-compressed one is refused (what = "DCD
 * trajectories", ...: named in the message) since frames are found by seeking. */
lc_status lci_bin_open(lc_device *dev, const char *path, const char *what, lci_bin *b);
void lci_bin_close(lci_bin *b);
/* Reads n bytes at off; past the end fails naming what was expected there. */
lc_status lci_bin_read(lci_bin *b, int64_t off, void *dst, size_t n, const char *what);

/* Values of the file's byte order from raw bytes. */
int32_t lci_bin_i32(const lci_bin *b, const void *p);
int64_t lci_bin_i64(const lci_bin *b, const void *p);
double lci_bin_f64(const lci_bin *b, const void *p);
/* Swaps n elements of width bytes in place when the file's order is not ours. */
void lci_bin_fix(const lci_bin *b, void *p, size_t n, size_t width);

/* The Fortran record starting at off: its length in *len (== expect unless
 * expect < 0), its data at off + marker, the trailing marker checked and the
 * whole record inside the file. *next = the offset after it. */
lc_status lci_bin_record(lci_bin *b, int64_t off, int64_t expect, const char *what, int64_t *len, int64_t *next);

/* Frames of self-delimiting records (XTC, TRR): header(b, off, k, frame,
 * &next, &eof) reads frame k's header at off into frame, sets next (the
 * offset after frame k) and eof = 1 when the file ends inside it. */
typedef lc_status (*lci_frame_header_fn)(lci_bin *b, int64_t off, int64_t k, void *frame, int64_t *next, int *eof);
/* Frame k's header into frame, by the headers of frames 0..k-1 (none of
 * their data is read); a k past the last frame fails naming the count. */
lc_status lci_bin_seek_frame(lci_bin *b, int64_t k, lci_frame_header_fn header, void *frame);
/* The whole frames; a last frame cut short is left out with a warning
 * (what = "an XTC frame", ... for an empty file's message). */
lc_status lci_bin_count_frames(lci_bin *b, lci_frame_header_fn header, void *frame, const char *what, int64_t *out);

#endif
