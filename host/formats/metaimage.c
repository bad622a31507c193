/* MetaImage (ITK's .mhd with a data file, .mha with attached data): 3-D
 * scalar volumes of MET_UCHAR, MET_USHORT, MET_SHORT or MET_FLOAT, raw or
 * zlib-compressed, either byte order. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/volume_data.h"

#define BAD(...) lci_error(r->dev, LC_ERROR_FORMAT, __VA_ARGS__)

/* One "key = value" line; *stop at ElementDataFile (the header ends there). */
static lc_status field(lci_header_lines *r, const char *k, const char *v, lci_vol_header *h, int *stop)
{
    const char *path = r->path;
    int ln = r->ln;
    if (!strcasecmp(k, "NDims")) {
        if (strcmp(v, "3") != 0) return BAD("%s:%d: NDims %s, only 3-D volumes are supported", path, ln, v);
    } else if (!strcasecmp(k, "DimSize")) {
        if (!lci_parse_sizes(v, h->size, 3))
            return BAD("%s:%d: DimSize \"%s\": expected three integers from 2 to 2147483647", path, ln, v);
        h->have_sizes = 1;
    } else if (!strcasecmp(k, "ElementType")) {
        if (!strcmp(v, "MET_UCHAR")) h->type = LC_VALUE_UINT8;
        else if (!strcmp(v, "MET_USHORT")) h->type = LC_VALUE_UINT16;
        else if (!strcmp(v, "MET_SHORT")) h->type = LC_VALUE_INT16;
        else if (!strcmp(v, "MET_FLOAT")) h->type = LC_VALUE_FLOAT32;
        else
            return BAD("%s:%d: ElementType %s is not supported (MET_UCHAR, MET_USHORT, MET_SHORT, MET_FLOAT)", path, ln,
                       v);
        h->have_type = 1;
    } else if (!strcasecmp(k, "ElementSpacing")) {
        if (!lci_parse_spacings(v, h->spacing, 3))
            return BAD("%s:%d: ElementSpacing \"%s\": expected three numbers from %g to %g", path, ln, v,
                       LCI_MIN_SPACING, LCI_MAX_COORD);
        h->have_spacing = 1;
    } else if (!strcasecmp(k, "Offset") || !strcasecmp(k, "Origin") || !strcasecmp(k, "Position")) {
        if (!lci_parse_doubles(v, h->origin, 3)) return BAD("%s:%d: %s \"%s\": expected three numbers", path, ln, k, v);
        h->have_origin = 1;
    } else if (!strcasecmp(k, "ElementByteOrderMSB") || !strcasecmp(k, "BinaryDataByteOrderMSB")) {
        if (strcasecmp(v, "True") && strcasecmp(v, "False"))
            return BAD("%s:%d: %s = %s: expected True or False", path, ln, k, v);
        h->big_endian = !strcasecmp(v, "True");
    } else if (!strcasecmp(k, "CompressedData")) {
        if (strcasecmp(v, "True") && strcasecmp(v, "False"))
            return BAD("%s:%d: CompressedData = %s: expected True or False", path, ln, v);
        h->gzip = !strcasecmp(v, "True");
        if (h->gzip && !LC_HAVE_ZLIB) return lci_missing_at(r, "CompressedData = True");
    } else if (!strcasecmp(k, "HeaderSize")) {
        if (!lci_parse_offset(v, &h->byte_skip))
            return BAD("%s:%d: HeaderSize \"%s\": expected an integer from -1 (data at the end of the file) to 2^62", path,
                       ln, v);
    } else if (!strcasecmp(k, "ElementDataFile")) {
        if (strcasecmp(v, "LOCAL") != 0) snprintf(h->data_file, sizeof h->data_file, "%s", v);
        *stop = 1;
    } else if (!strcasecmp(k, "ElementNumberOfChannels") && strcmp(v, "1") != 0) {
        return BAD("%s:%d: %s channels, only scalar volumes are supported", path, ln, v);
    }
    return LC_OK;
}

lc_status lci_mhd_header(lc_device *dev, const char *path, FILE *f, lci_vol_header *h)
{
    lci_header_lines r = {.dev = dev, .path = path, .f = f, .meta = 1};
    for (int stop = 0; !stop;) {
        char *k, *v;
        lc_status s = lci_header_next(&r, &k, &v);
        if (s == LC_OK && !k) break;
        if (s == LC_OK) s = field(&r, k, v, h, &stop);
        if (s != LC_OK) return s;
    }
    return lci_header_done(&r, h, "ElementType", "DimSize");
}

static lc_status mhd_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    return s != LC_OK ? s : lci_vol_read_with_header(dev, a->path, &o, lci_mhd_header, out);
}

const lci_format lci_format_metaimage = {
    .name = "metaimage", .kind = LC_KIND_GRID, .extensions = ".mhd .mha", .options = "type spacing origin",
    .description = "MetaImage: .mhd with a data file or .mha with attached data", .read = mhd_read};
