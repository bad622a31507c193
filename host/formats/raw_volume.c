/* Headerless voxels, x fastest: the sizes, type and byte order come from
 * the options. */
#include <string.h>
#include "host/formats/volume_data.h"

static lc_status raw_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    if (s != LC_OK) return s;
    if (o.size[0] <= 0 || o.size[1] <= 0 || o.size[2] <= 0 || o.type == LC_VALUE_DEFAULT)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: a raw volume needs its sizes and value type (--dims X,Y,Z --type T)", a->path);
    lci_vol_header h;
    memset(&h, 0, sizeof h);
    for (int i = 0; i < 3; i++) h.size[i] = o.size[i];
    h.type = o.type;
    h.big_endian = o.big_endian;
    return lci_vol_load(dev, a->path, a->path, 0, &h, &o, out);
}

const lci_format lci_format_raw_volume = {
    .name = "raw-volume", .kind = LC_KIND_GRID, .extensions = ".raw", .options = "size type spacing origin endian",
    .description = "headerless voxels, x fastest; size and type required", .read = raw_read};
