/* What the HDF5 reader's parts share (hdf5.c: datasets, the kind probe,
 * the guard; hdf5_snapshot.c: PartTypeN snapshots): libhdf5 calls that check
 * what a file declares before trusting it, and the reader's options. */
#ifndef LC_HDF5_IO_H
#define LC_HDF5_IO_H

#include "host/formats/format.h"
#include "host/formats/plist.h"
#include "host/formats/select.h"
#include "host/sph/sph_load.h"

#if LC_HAVE_HDF5
#include <hdf5.h>

#define LCI_H5_MAX_PARTICLES ((int64_t)1 << 31)

/* libhdf5's automatic error printing off while reading, and back after. */
typedef struct lci_h5_quiet {
    H5E_auto2_t fn;
    void *data;
} lci_h5_quiet;
void lci_h5_quiet_on(lci_h5_quiet *q);
void lci_h5_quiet_off(const lci_h5_quiet *q);

/* The deepest message on HDF5's error stack, or "". */
const char *lci_h5_why(void);

/* Opens path read-only after finding its signature (at 0, 512, 1024, ...). */
lc_status lci_h5_open(lc_device *dev, const char *path, hid_t *out);

int lci_h5_exists(hid_t loc, const char *name);

/* A dataset's shape (rank <= 3) and its place for messages ("byte N" of a contiguous one). */
typedef struct lci_h5_dinfo {
    int rank;
    hsize_t dims[3];
    H5T_class_t cls;
    size_t size;
    int is_signed;
    char where[64];
} lci_h5_dinfo;

/* ds's shape and type, failing (naming path and name) on a rank above 3, a
 * type that is not a number libhdf5 converts safely, or contiguous bytes
 * past the end of the file. */
lc_status lci_h5_dataset_info(lc_device *dev, const char *path, const char *name, hid_t ds, lci_h5_dinfo *d);

/* Reads all of ds as floats into out (n values), checking they are finite. */
lc_status lci_h5_read_floats(lc_device *dev, const char *path, const char *name, hid_t ds, const lci_h5_dinfo *di,
                             float *out, size_t n);

/* The /Header attribute name of 1 to n numbers as doubles into v[n] (the
 * rest 0): 1 when read, 0 when absent, -1 (with why) when present but empty,
 * longer than n or of a type libhdf5 does not convert safely. */
int lci_h5_header_attr(hid_t f, const char *name, double *v, hssize_t n, char *why, size_t wn);

/* The option value = none|mass|u|rho|hsml (aliases), or any dataset of
 * the groups by name (LCI_H5_V_NAMED: vs). */
enum { LCI_H5_V_NONE, LCI_H5_V_MASS, LCI_H5_V_U, LCI_H5_V_RHO, LCI_H5_V_HSML, LCI_H5_V_NAMED };
extern const char *const lci_h5_vnames[5];

typedef struct lci_h5_opts {
    int types[6], types_given, by_type, value, knn;
    lci_value_spec vs; /* value = a dataset: its path in the group and component */
    const char *vtext; /* the option as given ("none" when absent) */
    float radius, radius_scale;
    const char *dataset;
    lci_psel sel; /* select: index over the file's particles (type order), type = the PartType number */
    lci_sph_opts sph;
    lci_share *share; /* a share of the snapshot's particles (lci_read_args.share), or NULL */
} lci_h5_opts;

lc_status lci_h5_parse_opts(lc_device *dev, const lci_read_args *a, lci_h5_opts *o);

/* Keeps the particles [base, base + n) of p that the selection takes
 * (index first + i, type t; t < 0: no type), and their w8[] when w8 is not
 * NULL; returns how many. */
int64_t lci_h5_select_range(lci_psel *ps, lci_plist *p, size_t base, int64_t n, size_t first, int t, float *w8);

/* Radii of n points: radius option, else k-NN, zeros replaced by the smallest. */
lc_status lci_h5_fill_radii(lc_device *dev, const char *path, const lci_h5_opts *o, const float *x, int64_t n, float *r,
                            int have);

/* The particles of the PartTypeN groups of the open file f (hdf5_snapshot.c). */
lc_status lci_h5_read_snapshot(lc_device *dev, const char *path, hid_t f, lci_h5_opts *o, lci_loaded *out);

/* lanecast info: every PartTypeN group's per-particle datasets with their
 * shapes, into text (hdf5_snapshot.c). */
lc_status lci_h5_describe_snapshot(lc_device *dev, const char *path, hid_t f, char *text, size_t size);

#endif
#endif
