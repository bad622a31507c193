/* DICOM series (dicom.c, dicom_series.c): the files of an input, their
 * series, and one series' slices in order along the slice normal with the
 * voxel-to-world matrix they make. GDCM reads each file's header (the shim,
 * dicom_gdcm.h); everything here is lanecast's own logic. */
#ifndef LC_HOST_DICOM_H
#define LC_HOST_DICOM_H

#include <stdint.h>
#include "host/formats/dicom_gdcm.h"
#include "host/formats/format.h"

/* The top-level (7FE0,0010) Pixel Data element as the walk found it, and
 * what else it saw. */
typedef struct lci_dcm_pixel_el {
    int64_t at;        /* its byte offset; -1: the file has none, -2: not walked (a deflated data set) */
    int64_t value_at;  /* where its value starts */
    int64_t length;    /* its declared length; -1: undefined (encapsulated fragments) */
    int64_t fragments; /* undefined length: its items after the Basic Offset Table */
    int ambiguous;     /* GDCM may read the file otherwise than the walk did: no transfer syntax in a File
                          Meta Information (GDCM guesses it: a guess that read a length as 1.5 GB), or
                          an explicit-VR data set with elements without a VR (read as implicit; GDCM
                          re-reads such files in fallback modes, where it asserted:
                          tests/fuzz_regress/dicom-mixed-vr-assert) */
} lci_dcm_pixel_el;

typedef struct lci_dcm_file {
    char *path;
    lci_dcm_meta m;
    lci_dcm_pixel_el px;
} lci_dcm_file;

typedef struct lci_dcm_series {
    const char *uid; /* the first file's (0020,000E); "" when the files give none */
    int *files;      /* indices into lci_dcm_input.files, in file-name order */
    int nfiles;
} lci_dcm_series;

/* The DICOM files an input names and their series, numbered from 1 in the
 * order their first files sort by name. */
typedef struct lci_dcm_input {
    const char *where;  /* the input as given (a folder, a file), for messages */
    lci_dcm_file *files;
    int nfiles;
    lci_dcm_series *series;
    int nseries;
    int chosen; /* series of the single file given (0-based), -1 none */
} lci_dcm_input;

/* One slice of a series: a frame of a file, at a position. */
typedef struct lci_dcm_slice {
    int file, frame;
    double pos[3], key; /* key: the position along the slice normal */
} lci_dcm_slice;

/* A series as a volume: slices in increasing key, the voxel-to-world
 * matrix (column 0: one column step, 1: one row step, 2: one slice step,
 * 3: the first slice's first voxel), and what the files share. */
typedef struct lci_dcm_volume {
    const lci_dcm_series *series;
    lci_dcm_slice *slices;
    int nslices;
    int cols, rows;
    double m[3][4];
    double step;  /* distance between slices along the normal */
    double shear; /* degrees between the slices' line and the normal (gantry tilt) */
    const lci_dcm_meta *first; /* the first file's header (pixel format, modality) */
} lci_dcm_volume;

/* Finds the files of a.path (a folder; one file: itself when it holds
 * several frames, else the files of its folder in its series; the option
 * `files`: those, one per line), reads their headers and groups them into
 * series. */
lc_status lci_dcm_scan(lc_device *dev, const lci_read_args *a, lci_dcm_input *in);
void lci_dcm_input_free(lci_dcm_input *in);
/* The series the option `series` (N from 1, or a Series Instance UID)
 * names, else the only one (or the given file's); an error lists them. */
lc_status lci_dcm_choose(lc_device *dev, const lci_dcm_input *in, const lci_read_args *a, int *out);
/* Checks that series s's files make one volume (sizes, pixel format,
 * orientation, pixel spacing, decodable syntax, positions) and puts its
 * slices in order; uneven spacing fails, giving the spacings. */
lc_status lci_dcm_volume_of(lc_device *dev, const lci_dcm_input *in, int s, lci_dcm_volume *v);
void lci_dcm_volume_free(lci_dcm_volume *v);
/* Checks every element header of path (dicom_walk.c) before GDCM reads it:
 * each declared length within the file and its enclosing sequence or item,
 * sequences closed; 0 with the Pixel Data element in *px, or -1 with
 * "element (GGGG,EEEE) at byte N: ..." in err. */
int lci_dcm_walk(const char *path, lci_dcm_pixel_el *px, char *err, size_t errlen);
void lci_dcm_meta_free(lci_dcm_meta *m);
/* dicom_guard.c: what runs GDCM in the guard process (guard.h). The header
 * of a file the walk found ambiguous: 1 when the guard ran (0 in *rc and *m
 * filled, or -1 with why in err), 0 when no child could run. */
int lci_dcm_header_guarded(lc_device *dev, const char *path, lci_dcm_meta *m, int *rc, char *err, size_t errlen);
/* Every slice of v into raw (slice k at k x its bytes): native pixel data
 * read here, compressed data decoded by GDCM in guard children. */
lc_status lci_dcm_decode(lc_device *dev, const lci_dcm_input *in, const lci_dcm_volume *v, unsigned char *raw);

#endif
