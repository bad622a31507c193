/* XYZ: "element x y z" lines, optionally after a count line and a comment
 * line (repeated per frame in trajectories: the first frame is read).
 * Plain or gzip. Every error names the file and line. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"

static lc_status read_atoms(lci_text *t, lci_atoms *p)
{
    int rc;
    long declared = -1;
    int header_done = 0;
    while ((rc = lci_text_line(t)) == 1) {
        char el[16], xs[64], ys[64], zs[64];
        char *s = t->line;
        while (isspace((unsigned char)*s)) s++;
        if (!*s || *s == '#') continue;
        /* optional "count" + comment header (possibly repeated per frame: we read the first frame) */
        if (!header_done) {
            char *end;
            long c = strtol(s, &end, 10);
            while (isspace((unsigned char)*end)) end++;
            header_done = 1;
            if (end != s && !*end) {
                declared = c;
                if ((rc = lci_text_line(t)) != 1) break; /* comment line */
                continue;
            }
        }
        if (declared >= 0 && (long)p->n == declared) break; /* next frame */
        if (sscanf(s, "%15s %63s %63s %63s", el, xs, ys, zs) != 4)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected 'element x y z', got '%.*s'", t->path,
                             t->lineno, (int)(strcspn(s, "\r\n") < 60 ? strcspn(s, "\r\n") : 60), s);
        float x, y, z;
        if (lci_parse_float(xs, &x) || lci_parse_float(ys, &y) || lci_parse_float(zs, &z))
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: coordinates '%s %s %s' are not numbers", t->path,
                             t->lineno, xs, ys, zs);
        if (lci_atoms_add(p, x, y, z, el))
            return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
    }
    if (rc < 0) return LC_ERROR_IO;
    if (declared >= 0 && (long)p->n < declared)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: header declares %ld atoms but only %zu follow", t->path,
                         declared, p->n);
    return LC_OK;
}

static lc_status xyz_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o);
    if (s != LC_OK) return s;
    lci_text t;
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    s = read_atoms(&t, &p);
    lci_text_close(&t);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

const lci_format lci_format_xyz = {
    .name = "xyz", .kind = LC_KIND_PARTICLES, .extensions = ".xyz", .options = "radius radius_scale fields",
    .description = "XYZ: element x y z lines; the count and comment header is optional", .read = xyz_read};
