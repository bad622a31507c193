/* Atom selections (the `select` load option of the molecular formats): a
 * small language after VMD's and MDAnalysis's, parsed once and evaluated per
 * atom. Grammar (keywords case-insensitive):
 *
 *     expr    := term ('or' term)*
 *     term    := factor ('and' factor)*
 *     factor  := 'not' factor | '(' expr ')' | keyword
 *     keyword := 'all' | 'none' | 'protein' | 'backbone' | 'water' | 'ion' | 'solvent'
 *              | ('element' | 'name' | 'resname' | 'chain' | 'segid' | 'type') WORD+
 *              | ('index' | 'resid') RANGE+          RANGE := N | N:M (inclusive)
 *
 * WORDs may end in '*' (a prefix); element, name, resname and type compare
 * case-insensitively, chain and segid exactly. protein: a residue name of
 * the amino acids (and their CHARMM/AMBER protonation variants); water: HOH,
 * WAT, SOL, TIP3, TIP4, TIP5, SPC, ...; ion: NA, CL, K, MG, CA, ZN, SOD, CLA,
 * POT, ...; solvent: water or ion; backbone: names N CA C O of protein.
 * index counts the atoms of the frame from 0 in file order. */
#ifndef LC_HOST_SELECT_H
#define LC_HOST_SELECT_H

#include "host/internal.h"

/* What a file says about an atom; NULL (or has_resid 0) when the format
 * lacks it. */
typedef struct lci_atom_attr {
    const char *name, *resname, *chain, *segid, *type;
    long resid;
    int has_resid;
    /* loader extras, not seen by selections: the value of the `fields =
     * column:NAME` column (NULL: the atom lacks it) and k_i from the `value`
     * column (elements.h) */
    const char *column;
    float value;
} lci_atom_attr;

typedef struct lci_select lci_select;

/* Parses expr; errors (LC_ERROR_INVALID_ARGUMENT) name `what` (e.g. "x.pdb:
 * select") and the 1-based character position. */
lc_status lci_select_parse(lc_device *dev, const char *what, const char *expr, lci_select **out);
void lci_select_free(lci_select *s);
/* 1 if the atom matches, 0 if not. When the expression needs an attribute
 * the atom lacks, the atom does not match and *missing names the keyword. */
int lci_select_match(const lci_select *s, size_t index, const char *element, const lci_atom_attr *a,
                     const char **missing);

/* Residue classes the defaults use too. */
int lci_resname_water(const char *resname);
int lci_resname_ion(const char *resname);
int lci_resname_protein(const char *resname);

#endif
