/* Streaming gzip/zlib inflate from an open file with fixed buffers (issue
 * 13, class 5): nothing is read whole; lci_gz_read inflates straight into
 * the caller's buffer. A gzip file may hold several members one after
 * another (RFC 1952 section 2.2: `cat a.gz b.gz` is a valid file whose data
 * is both): they are read as one stream, like gunzip does. Any other bytes
 * after the last member are an error naming their offset and count (they
 * are not silently dropped). Needs zlib (LC_HAVE_ZLIB); without it opening
 * fails with the one "install zlib1g-dev" line. */
#ifndef LC_HOST_GZSTREAM_H
#define LC_HOST_GZSTREAM_H

#include <stdint.h>
#include <stdio.h>
#include "host/internal.h"

typedef struct lci_gz lci_gz;

/* Inflates f from byte `start` (a gzip member, or a zlib stream) to its end
 * of `size` bytes; path names the file in messages. f stays the caller's. */
lc_status lci_gz_open(lc_device *dev, const char *path, FILE *f, int64_t start, int64_t size, lci_gz **out);
void lci_gz_close(lci_gz *g);
/* Up to n inflated bytes into dst: the count (short only at the end of the
 * data), or -1 after an error (reported: corrupt or truncated data, trailing
 * bytes, read errors; each naming the compressed byte offset). */
long long lci_gz_read(lci_gz *g, void *dst, size_t n);
/* The next inflated byte (0..255), -1 at the end, -2 after an error (reported). */
int lci_gz_getc(lci_gz *g);
/* Compressed bytes consumed so far (for load progress). */
int64_t lci_gz_offset(const lci_gz *g);

#endif
