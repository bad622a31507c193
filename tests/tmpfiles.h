/* Small files the format tests write: tmp names their directory (set it
 * first), tpath(name) a file in it (eight buffers in turn, so a call can
 * take several), put() writes bytes, puts_() a string. */
#ifndef LC_TEST_TMPFILES_H
#define LC_TEST_TMPFILES_H

#include <stdio.h>
#include <string.h>

static const char *tmp;

static inline const char *tpath(const char *name)
{
    static char buf[8][1024];
    static int k;
    char *p = buf[k++ % 8];
    snprintf(p, sizeof buf[0], "%s/%s", tmp, name);
    return p;
}

static inline void put(const char *name, const void *data, size_t n)
{
    FILE *f = fopen(tpath(name), "wb");
    if (f) fwrite(data, 1, n, f), fclose(f);
}

static inline void puts_(const char *name, const char *text) { put(name, text, strlen(text)); }

#endif
