/* File formats as registry entries (STYLE.md "A format is a registry
 * entry"): each maps extensions and magic bytes to a kind and a reader that
 * turns bytes into that kind's public descriptor and nothing more. The
 * registry (registry.c) decides the format once, splits the options between
 * the format and the kind, and creates the volume through the kind's row.
 * Adding a format: one file here with its reader and one row in registry.c
 * (docs/DEVELOPERS.md "A new file format"). */
#ifndef LC_HOST_FORMAT_H
#define LC_HOST_FORMAT_H

#include "host/kinds/kind.h"

/* A share of a particle file (host/mpi/mpi_pload.c, dp.h "Particle parts"):
 * a reader of a format with `shares` reads the particles [a, b) of the
 * whole read's order only, a = total * rank / parts, b likewise for rank + 1,
 * over the rows of the file it would read (total), and returns them as the
 * whole read would (the same values, field ids and note). When the load
 * needs the whole set (k-nearest-neighbour radii, a selection, a radius
 * <= 0 replaced by a group's smallest) it says why in whole; what it
 * returned is then to be thrown away. */
typedef struct lci_share {
    int rank, parts;   /* in */
    size_t a, b, total; /* out: the rows read, of the total */
    size_t offset;     /* out: the returned particles before the first one (for messages) */
    const char *whole; /* out: why the set must be read whole, or NULL */
} lci_share;

/* What a reader gets: the file, the load request (frame, companion) and the
 * options meant for the format (the kind's build options are kept apart). */
typedef struct lci_read_args {
    const char *path;
    const lc_load_desc *desc; /* never NULL */
    const lc_option *options;
    int noptions;
    const char *format; /* the format's name (NULL from tests calling a reader directly) */
} lci_read_args;

/* The share the reader is to read (lci_read_volume_share sets it on the
 * device while the reader runs), or NULL: the whole file. */
static inline lci_share *lci_read_share(lc_device *dev) { return dev ? (lci_share *)dev->load_share : NULL; }

/* What a reader returns: the kind's descriptor (lc_particles_desc,
 * lc_grid_desc, ...) in desc, pointing into buffers listed in mem; the
 * registry frees both after creating the volume. */
#define LCI_LOADED_MEM 8
typedef struct lci_loaded {
    void *desc;
    void *mem[LCI_LOADED_MEM];
} lci_loaded;

/* Adds a buffer to free with the loaded data; returns p, or NULL (and frees
 * p) when the list is full. */
void *lci_loaded_keep(lci_loaded *l, void *p);
void lci_loaded_free(lci_loaded *l);

typedef struct lci_format {
    const char *name;        /* "pdb" */
    lc_kind kind;            /* LC_KIND_NONE: the file says (kind_of), e.g. HDF5 holds particles or volumes */
    const char *extensions;  /* ".pdb .ent": space-separated, lower case, matched case-insensitively
                                after a ".gz" is looked through */
    const char *options;     /* keys the reader takes, space-separated */
    const char *description;
    /* 1 if the first bytes (after gunzip when gzip) say this format; NULL: by extension only */
    int (*magic)(const unsigned char *head, size_t n);
    lc_status (*read)(lc_device *dev, const lci_read_args *a, lci_loaded *out);
    const char *package;     /* Debian package enabling it when compiled out, else NULL */
    /* trajectories: counts the frames (lc_file_probe); NULL = one frame, and
     * lc_load_desc.frame > 0 is refused */
    lc_status (*frames)(lc_device *dev, const char *path, int64_t *out);
    int companion;           /* 1: the reader uses lc_load_desc.companion */
    /* formats of kind LC_KIND_NONE: the kind this file (and load request)
     * holds; the reader then fills that kind's descriptor */
    lc_status (*kind_of)(lc_device *dev, const char *path, const lc_load_desc *desc, lc_kind *out);
    int folders;             /* 1: the reader takes a folder as its path (DICOM series) */
    /* lc_file_describe: lines about what the file holds beyond lc_file_info
     * (DICOM: its series), written into text (size bytes); NULL: nothing */
    lc_status (*describe)(lc_device *dev, const lci_read_args *a, char *text, size_t size);
    int shares;              /* 1: the reader reads a share of particles when lci_read_share(dev) returns one */
} lci_format;

/* The option of the given key, or NULL. */
const lc_option *lci_option_find(const lci_read_args *a, const char *key);

/* The readers (one file each family) */
extern const lci_format lci_format_xyz, lci_format_pdb, lci_format_gro, lci_format_raw_particles;
extern const lci_format lci_format_nrrd, lci_format_metaimage, lci_format_raw_volume;
extern const lci_format lci_format_rbf, lci_format_rbf_binary;
extern const lci_format lci_format_dcd, lci_format_lammps, lci_format_gadget;
extern const lci_format lci_format_xtc, lci_format_trr, lci_format_ncdf;
extern const lci_format lci_format_nifti, lci_format_vtk, lci_format_hdf5, lci_format_mmcif, lci_format_csv;
extern const lci_format lci_format_dicom;

/* Reads a structured volume's lc_grid_desc without creating the volume (the
 * RBF encoder's input); *format = the format's name. */
lc_status lci_read_grid(lc_device *dev, const char *path, const lc_load_desc *desc, const char **format,
                        lci_loaded *out);

/* What lc_volume_load reads before it creates the volume: the kind's
 * descriptor (in l->desc, the kind's load options applied; free with
 * lci_loaded_free), its kind and the format's name. desc is not NULL. For
 * host/mpi/, which distributes the data before creating each rank's part. */
lc_status lci_read_volume_desc(lc_device *dev, const char *path, const lc_load_desc *desc, lc_kind *kind,
                               const char **format, lci_loaded *l);
/* The same for a share of a particle file (lci_share; the format must have
 * `shares`, else LC_ERROR_UNSUPPORTED before anything is read). */
lc_status lci_read_volume_share(lc_device *dev, const char *path, const lc_load_desc *desc, lci_share *share,
                                lc_kind *kind, const char **format, lci_loaded *l);

#endif
