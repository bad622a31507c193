/* The topology of a coordinate-only trajectory (DCD, XTC, TRR, AMBER
 * NetCDF): a companion file that names each atom, read once and joined to
 * the frame's coordinates. PSF (psf.c), GROMACS .gro (its first frame) and
 * PDB (its first model) give the atom names, residues and elements; the
 * element sets the radius (elements.h), and the atom options (fields,
 * value, select) see what the topology says of each atom. */
#ifndef LC_HOST_TOPOLOGY_H
#define LC_HOST_TOPOLOGY_H

#include "host/formats/elements.h"

typedef struct lci_topo_atom {
    char name[9], resname[9], chain[2], segid[9], type[9], element[4];
    long resid;
    int has_resid;
    float charge, mass; /* PSF only */
} lci_topo_atom;

typedef enum { LCI_TOPO_NONE, LCI_TOPO_PSF, LCI_TOPO_GRO, LCI_TOPO_PDB } lci_topo_kind;

typedef struct lci_topo {
    lci_topo_kind kind;
    lci_topo_atom *atom;
    long natom, cap;
    int oom;
    char path[4096];
} lci_topo;

/* The topology of trajectory a->path: lc_load_desc.companion (its kind from
 * its extension, .psf/.gro/.pdb, after a ".gz"; else from its first bytes),
 * else the first of
 * STEM + each of exts (".psf", or ".gro .pdb .psf") that exists, else none
 * (t->kind = LCI_TOPO_NONE and *why says what was looked for). A topology
 * that fails to read fails the load, naming the trajectory and the
 * topology's own error. */
lc_status lci_topo_load(lc_device *dev, const lci_read_args *a, const char *exts, lci_topo *t, char *why, size_t n);
void lci_topo_free(lci_topo *t);

/* Per-atom numbers of the frame itself (TRR speeds and forces) that
 * `value = NAME` can take as k_i; NULL values: the frame lacks them. */
#define LCI_TRAJ_VALUES 2
typedef struct lci_traj_values {
    const char *name[LCI_TRAJ_VALUES];
    const float *v[LCI_TRAJ_VALUES];
} lci_traj_values;

/* The frame's atoms (xyz in Angstrom, natom of them) with the topology's
 * attributes, through the atom options of a (parsed here), handed to out as
 * an lc_particles_desc. Without a topology every atom gets one radius and a
 * warning quotes why; a column or value option then fails naming why. A
 * topology whose atom count differs fails. s != LC_OK: only frees. vals may
 * be NULL. */
lc_status lci_topo_atoms(lc_device *dev, const lci_read_args *a, lc_status s, const lci_topo *t, const char *why,
                         const float *xyz, int64_t natom, const lci_traj_values *vals, lci_loaded *out);

/* Adds an atom a topology reader (lci_atoms.capture) offers: 0 ok, -1 out of memory. */
int lci_topo_capture(lci_topo *t, const char *element, const lci_atom_attr *attr);

/* The first frame of a .gro file / first model of a PDB file into p's
 * capture (gro.c, pdb.c). */
lc_status lci_gro_topology(lc_device *dev, const char *path, lci_atoms *p);
lc_status lci_pdb_topology(lc_device *dev, const char *path, lci_atoms *p);

#endif
