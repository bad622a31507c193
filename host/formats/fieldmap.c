/* Field ids from attribute values (fieldmap.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/fieldmap.h"

int lci_fieldmap_id(lci_fieldmap *m, const char *value, int fold)
{
    for (int i = 0; i < m->n; i++)
        if (!(fold ? strncasecmp : strncmp)(m->names[i], value, sizeof m->names[0] - 1)) return i;
    if (m->n < LC_MAX_FIELDS) {
        snprintf(m->names[m->n], sizeof m->names[0], "%s", value);
        return m->n++;
    }
    return lci_fieldmap_merge(m, value, fold);
}

int lci_fieldmap_merge(lci_fieldmap *m, const char *value, int fold)
{
    m->merged++;
    int seen = 0;
    for (int i = 0; i < m->nextra && !seen; i++)
        seen = !(fold ? strncasecmp : strncmp)(m->extra[i], value, sizeof m->extra[0] - 1);
    if (!seen) {
        if (!m->extra) m->extra = calloc(LCI_FIELDMAP_EXTRA, sizeof *m->extra);
        if (m->extra && m->nextra < LCI_FIELDMAP_EXTRA) snprintf(m->extra[m->nextra++], sizeof m->extra[0], "%s", value);
        else m->extra_full = 1;
    }
    return LC_MAX_FIELDS - 1;
}

void lci_fieldmap_warn(lc_device *dev, const char *path, const char *what, const lci_fieldmap *m)
{
    if (!m->merged) return;
    const char *last = m->n == LC_MAX_FIELDS ? m->names[LC_MAX_FIELDS - 1] : "";
    lci_log(dev, LC_LOG_WARNING,
            "%s: fields by %s: %s%d more distinct values than the %d fields (first '%s') share field %d%s%s%s "
            "(%zu items)",
            path, what, m->extra_full ? "more than " : "", m->nextra, LC_MAX_FIELDS, m->extra ? m->extra[0] : "?",
            LC_MAX_FIELDS - 1, last[0] ? " with '" : "", last, last[0] ? "'" : "", m->merged);
}

void lci_fieldmap_free(lci_fieldmap *m)
{
    free(m->extra);
    m->extra = NULL;
}

static const char *const by_names[] = {"none", "element", "cpk", "type", "chain", "residue", "column"};

int lci_field_by_parse(const char *value, lci_field_by *by, const char **column)
{
    *column = NULL;
    for (int i = 0; i <= LCI_BY_RESIDUE; i++)
        if (!strcmp(value, by_names[i])) return *by = (lci_field_by)i, 0;
    if (!strncmp(value, "column:", 7) && value[7]) return *by = LCI_BY_COLUMN, *column = value + 7, 0;
    return -1;
}

const char *lci_field_by_name(lci_field_by by) { return by_names[by]; }
