/* First-of-each-atom alternate locations (altloc.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/altloc.h"

int lci_altloc_keep(lci_altlocs *a, const char *residue, const char *atom, int blank)
{
    if (strncmp(a->residue, residue, sizeof a->residue - 1)) {
        snprintf(a->residue, sizeof a->residue, "%s", residue);
        a->n = 0;
    }
    if (blank) return 1;
    for (size_t i = 0; i < a->n; i++)
        if (!strncmp(a->kept[i], atom, sizeof a->kept[0] - 1)) return a->skipped++, 0;
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 32;
        void *k = realloc(a->kept, cap * sizeof a->kept[0]);
        if (!k) return -1;
        a->kept = k;
        a->cap = cap;
    }
    snprintf(a->kept[a->n++], sizeof a->kept[0], "%s", atom);
    return 1;
}

void lci_altlocs_free(lci_altlocs *a)
{
    free(a->kept);
    memset(a, 0, sizeof *a);
}
