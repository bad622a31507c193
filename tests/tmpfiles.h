/* Small files the format tests write: tmp names their directory (set it
 * first), tpath(name) a file in it (eight buffers in turn, so a call can
 * take several), put() writes bytes, puts_() a string; load_must_fail()
 * checks a load's failure and its message. */
#ifndef LC_TEST_TMPFILES_H
#define LC_TEST_TMPFILES_H

#include <stdio.h>
#include <string.h>

#include "check.h"
#include "lanecast/lanecast.h"

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

/* lc_volume_load(path) must fail with want and one line that starts with
 * "PATH<where>" and holds says (and says2 unless NULL). */
static inline void load_must_fail(lc_device *dev, const char *path, const char *where, const char *says,
                                  const char *says2, lc_status want, const lc_load_desc *d)
{
    char prefix[1200];
    snprintf(prefix, sizeof prefix, "%s%s", path, where);
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, path, d, &v);
    const char *m = lc_last_error();
    CHECK(s == want && !v && !strncmp(m, prefix, strlen(prefix)) && strstr(m, says) && (!says2 || strstr(m, says2)) &&
              !strchr(m, '\n'),
          "%s fails (%s ... %s): %s", path, where, says, m);
    lc_volume_destroy(v);
}

#endif
