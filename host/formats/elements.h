/* Atoms of the molecular formats (XYZ, PDB, GRO): the covalent radius of an
 * element (Knoll 2014 §3.1; radii from Cordero et al. 2008, Dalton Trans.),
 * one field per element when asked (`fields = element`), and the growing
 * atom list a reader fills and hands over as an lc_particles_desc. */
#ifndef LC_HOST_ELEMENTS_H
#define LC_HOST_ELEMENTS_H

#include "host/formats/format.h"
#include "host/formats/select.h"
#include "host/formats/fieldmap.h"

#define LCI_DEFAULT_RADIUS 1.5f /* of an element not in the table */

/* Covalent radius in Angstrom of an element symbol (case-insensitive), or 0 if unknown. */
float lci_element_radius(const char *sym);

/* The options every molecular format takes: radius, radius_scale, fields
 * (alias field_by: none, element, cpk, type, chain, residue, or column:NAME
 * for the formats with named columns, LCI_COLUMN_FORMATS; distinct values
 * beyond 8 share field 7, with a warning) and select (select.h). fields = cpk gives fixed
 * fields by element class: 0 C, 1 N, 2 O, 3 S, 4 P, 5 H, 6 any other
 * element, and 7 solvent (water and ions by residue name, any element) when
 * the atoms read hold something besides solvent; nfields = 1 + the largest
 * id used. */
#define LCI_CPK_SOLVENT 7
#define LCI_COLUMN_FORMATS "pdb mmcif dcd xtc trr ncdf" /* formats taking fields = column:NAME and value = COLUMN */
typedef struct lci_atom_opts {
    float radius;       /* > 0: every atom's radius */
    float radius_scale; /* > 0: scales the element radii */
    int fields_by_element;
    int cpk;
    lci_field_by by_attr; /* LCI_BY_TYPE, _CHAIN, _RESIDUE, _COLUMN: fields by that attribute; else NONE */
    const char *column;   /* fields = column:NAME (PDB, mmCIF, DCD's PSF): the reader resolves NAME and gives
                             each atom's value in lci_atom_attr.column */
    const char *value;    /* value = COLUMN (same formats): k_i from lci_atom_attr.value; NULL: none */
    const char *format;   /* for messages */
    char select[1024];  /* "" = every atom */
} lci_atom_opts;

/* Parses the keys above among a's options (errors name the key). */
lc_status lci_atom_options(lc_device *dev, const lci_read_args *a, lci_atom_opts *o);

typedef struct lci_atoms {
    float *xyz, *r;
    uint8_t *field;
    float *v;                      /* k_i when o.value is set, else NULL */
    size_t n, cap;
    lci_fieldmap fm;               /* element or attribute of each field */
    int nnames;                    /* fields used (cpk) */
    int field_missing;             /* atoms without the attribute fields are by */
    lci_atom_opts o;
    int unknown;                   /* atoms whose element is not in the table */
    char first_unknown[16];
    size_t seen;                   /* atoms offered (the selection's index) */
    lci_select *sel;               /* parsed on the first atom */
    const char *sel_missing;       /* a keyword the file could not answer */
    uint8_t *solvent;              /* cpk: 1 per solvent atom */
    size_t nsolvent;
    struct lci_topo *capture;      /* set: atoms go to the topology (topology.h), unselected, not here */
} lci_atoms;

/* An atom of element sym at (x, y, z): its radius and field from the element
 * and the options; skipped when the selection rejects it. attr: what the
 * file says about the atom (NULL: the element only). 0 ok, -1 out of memory. */
int lci_atoms_add(lci_atoms *p, float x, float y, float z, const char *sym);
int lci_atoms_add_attr(lci_atoms *p, float x, float y, float z, const char *sym, const lci_atom_attr *attr);
void lci_atoms_free(lci_atoms *p);
/* When s is LC_OK, hands the atoms over to out as an lc_particles_desc (and
 * warns once about unknown elements); else frees them. Returns s or an
 * out-of-memory error. */
lc_status lci_atoms_finish(lc_device *dev, const char *path, lc_status s, lci_atoms *p, lci_loaded *out);

#endif
