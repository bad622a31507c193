/* Atoms of the molecular formats (XYZ, PDB, GRO): the covalent radius of an
 * element (Knoll 2014 §3.1; radii from Cordero et al. 2008, Dalton Trans.),
 * one field per element when asked (`fields = element`), and the growing
 * atom list a reader fills and hands over as an lc_particles_desc. */
#ifndef LC_HOST_ELEMENTS_H
#define LC_HOST_ELEMENTS_H

#include "host/formats/format.h"

#define LCI_DEFAULT_RADIUS 1.5f /* of an element not in the table */

/* Covalent radius in Angstrom of an element symbol (case-insensitive), or 0 if unknown. */
float lci_element_radius(const char *sym);

/* The options every molecular format takes: radius, radius_scale, fields. */
typedef struct lci_atom_opts {
    float radius;       /* > 0: every atom's radius */
    float radius_scale; /* > 0: scales the element radii */
    int fields_by_element;
} lci_atom_opts;

/* Parses the keys above among a's options (errors name the key). */
lc_status lci_atom_options(lc_device *dev, const lci_read_args *a, lci_atom_opts *o);

typedef struct lci_atoms {
    float *xyz, *r;
    uint8_t *field;
    size_t n, cap;
    char names[LC_MAX_FIELDS][16]; /* element of each field (fields_by_element) */
    int nnames;
    lci_atom_opts o;
    int unknown;                   /* atoms whose element is not in the table */
    char first_unknown[16];
} lci_atoms;

/* An atom of element sym at (x, y, z): its radius and field from the element
 * and the options. 0 ok, -1 out of memory. */
int lci_atoms_add(lci_atoms *p, float x, float y, float z, const char *sym);
void lci_atoms_free(lci_atoms *p);
/* When s is LC_OK, hands the atoms over to out as an lc_particles_desc (and
 * warns once about unknown elements); else frees them. Returns s or an
 * out-of-memory error. */
lc_status lci_atoms_finish(lc_device *dev, const char *path, lc_status s, lci_atoms *p, lci_loaded *out);

#endif
