/* Writes a gzip file (RFC 1952) of stored deflate blocks (RFC 1951 §3.2.4),
 * so tests can make gzip input without zlib (the -Dzlib=disabled build). */
#ifndef LC_TEST_GZIP_STORED_H
#define LC_TEST_GZIP_STORED_H

#include <stdint.h>
#include <stdio.h>

static uint32_t gzs_crc32(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void gzs_le32(FILE *f, uint32_t v)
{
    for (int i = 0; i < 4; i++) fputc((int)((v >> (8 * i)) & 0xff), f);
}

/* 0 ok, -1 if the file cannot be written. */
static int gzs_write(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    static const unsigned char hdr[10] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3};
    fwrite(hdr, 1, sizeof hdr, f);
    const unsigned char *p = data;
    size_t done = 0;
    do {
        size_t k = n - done > 65535 ? 65535 : n - done;
        fputc(done + k == n ? 1 : 0, f); /* BFINAL, BTYPE = 00 (stored) */
        fputc((int)(k & 0xff), f), fputc((int)(k >> 8), f);
        fputc((int)(~k & 0xff), f), fputc((int)((~k >> 8) & 0xff), f);
        fwrite(p + done, 1, k, f);
        done += k;
    } while (done < n);
    gzs_le32(f, gzs_crc32(p, n));
    gzs_le32(f, (uint32_t)n);
    return fclose(f) ? -1 : 0;
}

#endif
