/* What the volume formats (NRRD, MetaImage, raw) share: the header a
 * format's parser fills, the "key: value" / "key = value" line reader, the
 * options (size, type, spacing, origin, endian), and the voxel reading
 * (raw or zlib/gzip, either endianness) that ends in an lc_grid_desc. */
#ifndef LC_HOST_VOLUME_DATA_H
#define LC_HOST_VOLUME_DATA_H

#include <stdio.h>
#include "host/formats/format.h"

/* What a header says about the voxels. */
typedef struct lci_vol_header {
    int64_t size[3];
    lc_value_type type;
    double spacing[3];
    int have_spacing;
    double origin[3];
    int have_origin;
    int have_type, have_sizes;
    int gzip;             /* 1: gzip/zlib stream */
    int big_endian;
    char data_file[1024]; /* "" = attached after the header */
    long long byte_skip;  /* -1: the data is the file's last bytes */
    long data_offset;     /* attached: where the header ends */
} lci_vol_header;

/* The options these formats take (lci_format.options). */
typedef struct lci_vol_opts {
    int size[3];
    lc_value_type type;
    lc_vec3 spacing, origin;
    int big_endian;
} lci_vol_opts;

lc_status lci_vol_options(lc_device *dev, const lci_read_args *a, lci_vol_opts *o);

/* Header lines of `path` read from f: NRRD ("field: value", ends at a blank
 * line) or MetaImage ("key = value"). */
typedef struct lci_header_lines {
    lc_device *dev;
    const char *path;
    FILE *f;
    int meta; /* 1: MetaImage syntax */
    int ln;   /* line number of the last line read */
    char line[4096];
} lci_header_lines;

/* The next key and value (trimmed, pointing into r->line), skipping blank
 * lines and comments; *key = NULL at the end of the header. */
lc_status lci_header_next(lci_header_lines *r, char **key, char **value);
/* The error for a header asking for a feature this build lacks, naming the line. */
lc_status lci_missing_at(const lci_header_lines *r, const char *what);
/* Checks that the header gave a type and sizes (named as the format calls
 * them) and notes where it ended. */
lc_status lci_header_done(lci_header_lines *r, lci_vol_header *h, const char *type_key, const char *sizes_key);

/* Numbers of a header value: n doubles (separated by white space, commas or
 * parentheses) or exactly n integers. 1 ok, 0 not. */
int lci_parse_doubles(const char *v, double *out, int n);
/* n integers from 2 to 2^31-1 (no sign), nothing else */
int lci_parse_sizes(const char *v, int64_t *out, int n);
/* n numbers in [LCI_MIN_SPACING, LCI_MAX_COORD] (0 0 0 is not a default) */
int lci_parse_spacings(const char *v, double *out, int n);
/* A byte offset (NRRD byte skip, MetaImage HeaderSize): one integer from -1
 * (both formats: the data is the last bytes of its file) to LCI_MAX_OFFSET,
 * nothing else on the line; 1 ok, 0 not. */
int lci_parse_offset(const char *v, long long *out);
#define LCI_MAX_OFFSET (1LL << 62) /* so that header end + offset cannot overflow */

/* Geometry lanecast can render in float: spacings in [LCI_MIN_SPACING,
 * LCI_MAX_COORD] and |origin| + (n - 1) * spacing <= LCI_MAX_COORD along
 * each axis (so extents, the diagonal and 16 / diagonal stay finite);
 * otherwise LC_ERROR_INVALID_ARGUMENT naming the file, the axis and the values. */
#define LCI_MIN_SPACING 1e-30
#define LCI_MAX_COORD 1e30
lc_status lci_vol_geometry(lc_device *dev, const char *path, const int size[3], lc_vec3 spacing, lc_vec3 origin);

/* Hands a read volume over as out's lc_grid_desc d (allocated by the caller;
 * out keeps d and data from here on): size, type, the file's spacing and
 * origin unless the options override them, then checks the geometry. */
lc_status lci_vol_hand_over(lc_device *dev, const char *path, lc_grid_desc *d, const int64_t size[3], lc_value_type type,
                            const double spacing[3], const double origin[3], const lci_vol_opts *o, void *data,
                            lci_loaded *out);

/* Reads the header of `path` with parse (which fills h from the open file),
 * finds the data (detached: relative to the header's folder), and loads it. */
typedef lc_status (*lci_header_fn)(lc_device *dev, const char *path, FILE *f, lci_vol_header *h);
lc_status lci_vol_read_with_header(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                                   lci_loaded *out);
/* Reads the voxels h describes from data_path at offset and hands them over
 * as an lc_grid_desc (options override spacing and origin). Errors name path. */
lc_status lci_vol_load(lc_device *dev, const char *path, const char *data_path, long long offset,
                       const lci_vol_header *h, const lci_vol_opts *o, lci_loaded *out);

/* Where the voxels of a volume file lie, for reading a part of them
 * (host/mpi/window.c): uncompressed values of `type` from byte `offset` of
 * data_path, the file's axes fsize (its first fastest); grid axis w is
 * file axis perm[w], reversed when flip[w]; grid is the lc_grid_desc the
 * whole load gives (data NULL). */
typedef struct lci_vol_layout {
    char data_path[2048];
    long long offset;
    int64_t fsize[3];
    lc_value_type type;
    int swap; /* big-endian values */
    int perm[3], flip[3];
    lc_grid_desc grid;
    char dataset[256]; /* HDF5: the grid's dataset, read by hyperslab (lci_hdf5_read_box); "" otherwise */
    int chunked;       /* HDF5: the dataset is chunked (its chunk index is walked in the guard first) */
} lci_vol_layout;

/* The layout of a header format's file (LC_ERROR_UNSUPPORTED, with a
 * message, for compressed data); the checks of a whole load on the header
 * and the data file's size, without reading voxels. */
lc_status lci_vol_layout_of(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                            lci_vol_layout *l);
lc_status lci_vol_layout_from_header(lc_device *dev, const char *path, const char *data_path, long long offset,
                                     const lci_vol_header *h, const lci_vol_opts *o, lci_vol_layout *l);
/* Fills l->grid and l->type as lci_vol_hand_over would the desc. */
lc_status lci_vol_layout_grid(lc_device *dev, const char *path, const int64_t size[3], lc_value_type type,
                              const double spacing[3], const double origin[3], const lci_vol_opts *o, lci_vol_layout *l);
/* The headers of NRRD and MetaImage files (nrrd.c, metaimage.c). */
lc_status lci_nrrd_header(lc_device *dev, const char *path, FILE *f, lci_vol_header *h);
lc_status lci_mhd_header(lc_device *dev, const char *path, FILE *f, lci_vol_header *h);
/* A NIfTI file's layout when its voxels can be read in parts: one
 * uncompressed 3-D frame `frame` of uint8, int16, uint16 or float32,
 * unscaled; else LC_ERROR_UNSUPPORTED (read whole). nifti.c. */
lc_status lci_nifti_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l);
/* An HDF5 file's 3-D dataset (option dataset = PATH) as a grid read in
 * parts: its layout (C order: identity axes, no swap; the options' spacing
 * and origin as the whole read's), its metadata checked in the guard
 * process (guard.c) first; LC_ERROR_UNSUPPORTED without libhdf5. The box
 * start[3], count[3] of nodes (x, y, z) into out (x fastest, l->type) by
 * one hyperslab read, run in the guard first when the dataset is chunked
 * (libhdf5 walks the chunk index as it reads). hdf5.c. */
lc_status lci_hdf5_grid_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l);
lc_status lci_hdf5_read_box(lc_device *dev, const lci_vol_layout *l, const int64_t start[3], const int64_t count[3],
                            void *out);

#endif
