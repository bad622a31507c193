/* CHARMM/NAMD/X-PLOR protein structure files (.psf): the atoms of the
 * !NATOM section, each with its name, type, mass and the element lanecast
 * gives it (psf.c). Read as the topology (companion) of a DCD trajectory. */
#ifndef LC_HOST_PSF_H
#define LC_HOST_PSF_H

#include "host/internal.h"

typedef struct lci_psf_atom {
    char name[9], type[9], element[4], segid[9], resname[9];
    long resid;
    float charge, mass;
} lci_psf_atom;

typedef struct lci_psf {
    lci_psf_atom *atom;
    long natom;
} lci_psf;

/* Reads the atoms; errors name the file and the line. */
lc_status lci_psf_read(lc_device *dev, const char *path, lci_psf *out);
void lci_psf_free(lci_psf *p);

#endif
