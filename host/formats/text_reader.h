/* Reading a particle file that may be gzip-compressed: lines for text
 * formats, bytes for raw ones. Plain files go through stdio and gzip files
 * through zlib; the reader counts lines so every error can name one. Also
 * the small fixed-column and number parsers the text formats share. */
#ifndef LC_HOST_TEXT_READER_H
#define LC_HOST_TEXT_READER_H

#include <stdio.h>
#include "host/internal.h"

#define LCI_LINE_MAX 4096

typedef struct lci_text {
    lc_device *dev;
    const char *path;
    FILE *f;   /* the file (plain or compressed) */
    struct lci_gz *gz; /* the inflate stream when the file is gzip-compressed (gzstream.h), or NULL */
    char line[LCI_LINE_MAX]; /* up to LCI_LINE_MAX - 1 characters (not counting a newline) */
    long lineno; /* of the line in `line`, 1-based */
    long long size; /* bytes in the file (compressed for gzip), for load progress */
} lci_text;

/* Opens path (gzip when its first bytes say so; a regular file, else an
 * error: checked.h); errors name the file. */
lc_status lci_text_open(lc_device *dev, const char *path, lci_text *t);
void lci_text_close(lci_text *t);
/* Reads the next line into t->line (with its newline when it fits; a final
 * line needs none): 1 ok, 0 at the end, -1 error (reported, naming the file
 * and line): a line over LCI_LINE_MAX - 1 characters, a NUL byte in it. */
int lci_text_line(lci_text *t);
/* Reads up to n bytes into dst: the count read (short only at the end), or
 * -1 on a read error (reported). */
long long lci_text_read(lci_text *t, void *dst, size_t n);

/* The first bytes of path (inflated when gzip) and whether it is gzip. */
lc_status lci_file_head(lc_device *dev, const char *path, unsigned char *head, size_t cap, size_t *n, int *gzip);

/* The whole of s (surrounding white space allowed) as a finite-range float:
 * 0 ok, -1 not a number. */
int lci_parse_float(const char *s, float *out);
/* Columns a..b (1-based, inclusive) of line, trimmed, into out (n bytes). */
void lci_column(const char *line, int a, int b, char *out, size_t n);

#endif
