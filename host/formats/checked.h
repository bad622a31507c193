/* Opening input files and allocating sizes computed from file data, checked
 * (issue 13, classes 3 and 5): a file a reader opens (the input itself, a
 * header's data file, a companion) must be a regular file, found out
 * without blocking on a FIFO or device; every buffer whose size comes from
 * a header or a count in a file is checked for overflow and against the
 * memory limit before it is allocated, and refused with a message giving
 * the bytes needed and allowed. */
#ifndef LC_HOST_CHECKED_H
#define LC_HOST_CHECKED_H

#include <stdint.h>
#include <stdio.h>
#include "host/internal.h"

/* Opens path ("rb") if it is a regular file; *size = its bytes (size may be
 * NULL). A directory, FIFO, socket or device fails with LC_ERROR_IO and one
 * message: "OWNER: its data file PATH: ..." when owner is not NULL (a
 * header naming the file), else "PATH: ...". */
lc_status lci_open_regular(lc_device *dev, const char *path, const char *owner, FILE **out, int64_t *size);

/* The memory limit of the load in progress: lc_load_desc option max_memory
 * (dev->load_max_memory), else 3/4 of the physical memory (sysconf), else
 * no limit. */
uint64_t lci_memory_limit(const lc_device *dev);
/* "8G", "512M", "64K", "1.5G", "1000000" (bytes; K, M, G, T are powers of
 * 1024, an optional trailing "B" or "iB"): 0 ok, -1 not a size. 0 is not a size. */
int lci_parse_memory(const char *s, uint64_t *out);

/* count * elem + extra bytes for `what` ("voxels", "particles", ...) of
 * file: *bytes = the sum, or an error (overflow, or over the memory limit)
 * naming the file, the bytes needed and the bytes allowed. */
lc_status lci_size_check(lc_device *dev, const char *file, uint64_t count, uint64_t elem, uint64_t extra,
                         const char *what, uint64_t *bytes);
/* lci_size_check, then malloc (calloc when zero is set); NULL after an error
 * (reported). The one way readers allocate buffers sized by file data. */
void *lci_alloc_checked(lc_device *dev, const char *file, uint64_t count, uint64_t elem, uint64_t extra,
                        const char *what, int zero);

#endif
