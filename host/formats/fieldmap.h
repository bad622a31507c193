/* Field ids from an attribute's values (`field_by` / `fields` load option:
 * element, type, chain, residue, column:NAME): the first LC_MAX_FIELDS
 * distinct values get ids 0..7 in order of first appearance; further values
 * share the last field, and lci_fieldmap_warn says how many were merged
 * (one warning per file). Every format mapping values to fields goes
 * through here, so a 9th distinct value merges the same way in all of them. */
#ifndef LC_HOST_FIELDMAP_H
#define LC_HOST_FIELDMAP_H

#include <stddef.h>
#include "host/internal.h"

#define LCI_FIELDMAP_EXTRA 256 /* distinct merged values counted exactly; beyond: "more than" */

typedef struct lci_fieldmap {
    char names[LC_MAX_FIELDS][32];
    int n;
    char (*extra)[32]; /* merged values seen (allocated on the first) */
    int nextra, extra_full;
    size_t merged;     /* items given the shared last field for a merged value */
} lci_fieldmap;

/* The field id of value (case-sensitive unless fold); grows the map. */
int lci_fieldmap_id(lci_fieldmap *m, const char *value, int fold);
/* Counts value as merged into the shared last field (for formats whose ids
 * are numbers: ids 0..7 as they are, larger ones through here); returns
 * LC_MAX_FIELDS - 1. */
int lci_fieldmap_merge(lci_fieldmap *m, const char *value, int fold);
/* Warns (when values were merged) naming the file and what was mapped. */
void lci_fieldmap_warn(lc_device *dev, const char *path, const char *what, const lci_fieldmap *m);
void lci_fieldmap_free(lci_fieldmap *m);

/* What a `fields` (alias `field_by`) option value asks for. */
typedef enum lci_field_by {
    LCI_BY_NONE = 0, LCI_BY_ELEMENT, LCI_BY_CPK, LCI_BY_TYPE, LCI_BY_CHAIN, LCI_BY_RESIDUE, LCI_BY_COLUMN
} lci_field_by;
/* Parses value ("none", "element", "cpk", "type", "chain", "residue",
 * "column:NAME"); -1 when it is none of those. *column = NAME. */
int lci_field_by_parse(const char *value, lci_field_by *by, const char **column);
const char *lci_field_by_name(lci_field_by by);

#endif
