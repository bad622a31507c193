/* Raw particles: little-endian float32 x y z triples, nothing else; the
 * count and the radius come from the options. Plain or gzip. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"

static lc_status read_xyz(lci_text *t, size_t n, float radius, lci_atoms *p)
{
    if (n == 0) return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: raw particles need a count", t->path);
    if (!(radius > 0.0f))
        return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: raw particles need a radius (> 0)", t->path);
    if (n > (size_t)INT32_MAX / 2)
        return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: %zu particles is too many", t->path, n);
    /* sizes before allocating (fuzz_raw_particles: a count of 888888884 for
     * 48 bytes reserved 14 GB): a plain file must hold at least 12 n bytes
     * (a longer one fails below, naming the count),
     * a gzip one cannot inflate to more than 1032 times its size (deflate's
     * limit) */
    long long need = (long long)n * 12;
    struct stat st;
    int regular = t->f && fstat(fileno(t->f), &st) == 0 && S_ISREG(st.st_mode);
    if ((regular && (long long)st.st_size < need) || (t->gz && t->size > 0 && need / 1032 > t->size))
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: holds %lld%s bytes, but %zu particles need %lld (12 bytes each)",
                         t->path, regular ? (long long)st.st_size : t->size * 1032, regular ? "" : " (at most, inflated)",
                         n, need);
    p->xyz = malloc(n * 3 * sizeof(float));
    p->r = malloc(n * sizeof(float));
    p->field = calloc(n, 1);
    if (!p->xyz || !p->r || !p->field)
        return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu particles", t->path, n);
    size_t want = n * 3 * sizeof(float);
    long long got = lci_text_read(t, p->xyz, want);
    if (got < 0) return LC_ERROR_IO;
    if ((size_t)got != want)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: holds %lld bytes, but %zu particles need %zu (12 bytes each)",
                         t->path, got, n, want);
    char extra;
    if (lci_text_read(t, &extra, 1) == 1)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: longer than %zu particles x 12 bytes; wrong count?", t->path, n);
    for (size_t i = 0; i < n; i++) p->r[i] = radius;
    p->n = p->cap = n;
    return LC_OK;
}

static lc_status raw_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o); /* radius */
    size_t count = 0;
    const lc_option *x;
    if (s == LC_OK && (x = lci_option_find(a, "count")))
        s = lci_option_size(dev, a->path, x, (size_t)INT32_MAX / 2, &count);
    if (s != LC_OK) return s;
    lci_text t;
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    s = read_xyz(&t, count, p.o.radius, &p);
    lci_text_close(&t);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

const lci_format lci_format_raw_particles = {
    .name = "raw-particles", .kind = LC_KIND_PARTICLES, .extensions = ".f32", .options = "count radius",
    .description = "raw little-endian float32 x y z triples; count and radius required", .read = raw_read};
