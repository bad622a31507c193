/* Alternate locations of the molecular formats (PDB altLoc, mmCIF
 * label_alt_id): of the alternates of one atom, the first in the file is
 * kept (usually 'A', but a residue listing only 'B' and 'C' keeps 'B') and
 * the others are skipped, so a disordered side chain is drawn once. An atom
 * is its residue (chain, number, insertion code) and its name; alternates of
 * one residue lie inside that residue's records, as wwPDB files order them. */
#ifndef LC_HOST_ALTLOC_H
#define LC_HOST_ALTLOC_H

#include <stddef.h>

typedef struct lci_altlocs {
    char residue[32];  /* the residue of the records being read */
    char (*kept)[8];   /* names of its atoms kept with an altloc */
    size_t n, cap;
    size_t skipped;    /* records skipped over the whole file */
} lci_altlocs;

/* 1: keep this record, 0: skip it (an alternate of an atom already kept),
 * -1: out of memory. blank: the record has no alternate location. */
int lci_altloc_keep(lci_altlocs *a, const char *residue, const char *atom, int blank);
void lci_altlocs_free(lci_altlocs *a);

#endif
