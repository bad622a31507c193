/* The particle list of the non-molecular particle formats (LAMMPS dumps,
 * GADGET snapshots): positions, radii, values and field ids growing with the
 * records read, handed over as an lc_particles_desc; and radii from the
 * distance to the k-th nearest neighbour (a uniform-grid search). */
#ifndef LC_HOST_PLIST_H
#define LC_HOST_PLIST_H

#include "host/formats/format.h"
#include "host/formats/select.h"
#include "host/formats/fieldmap.h"

/* The `select` option for particle formats (LAMMPS: type = atom type, index;
 * GADGET: type = particle type 0..5, index over the file's particles). */
typedef struct lci_psel {
    lci_select *sel; /* NULL: no selection */
    const char *expr, *missing;
    size_t seen;
    const char *gives; /* what the file answers, for the message on a keyword it cannot ("index and type");
                          NULL: the LAMMPS/GADGET wording */
} lci_psel;
lc_status lci_psel_open(lc_device *dev, const lci_read_args *a, lci_psel *ps);
/* 1 keep, 0 drop the particle of this index. */
int lci_psel_keep(lci_psel *ps, size_t index, const char *element, const lci_atom_attr *attr);
/* After reading: a keyword the file could not answer, or nothing selected, fails (s kept when not LC_OK). */
lc_status lci_psel_close(lc_device *dev, const lci_read_args *a, lci_psel *ps, size_t kept, lc_status s);

typedef struct lci_plist {
    float *xyz, *r, *v;
    uint8_t *f;
    size_t n, cap;
} lci_plist;

/* Reserves room for n more particles: 0 ok, -1 out of memory. */
int lci_plist_reserve(lci_plist *p, size_t n);
/* Appends one particle: 0 ok, -1 out of memory. */
int lci_plist_add(lci_plist *p, float x, float y, float z, float r, float v, uint8_t f);
void lci_plist_free(lci_plist *p);
/* When s is LC_OK, hands the list over as an lc_particles_desc with nfields
 * fields (values NULL when with_values is 0); else frees it. */
lc_status lci_plist_finish(lc_device *dev, const char *path, lc_status s, lci_plist *p, int nfields, int with_values,
                           lci_loaded *out);

/* r[i] = the distance from xyz[i] to its k-th nearest other point of the n
 * (k clamped to n - 1); 0 ok, -1 out of memory. Coincident points may give 0. */
int lci_knn_radii(const float *xyz, size_t n, int k, float *r);

#endif
