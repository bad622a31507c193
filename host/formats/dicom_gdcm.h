/* The GDCM shim (dicom_gdcm.cpp): what the DICOM reader (dicom.c) asks of
 * GDCM, in C types. Every call catches GDCM's exceptions and returns 0 or
 * -1 with a message in err; nothing else crosses the boundary. */
#ifndef LC_HOST_DICOM_GDCM_H
#define LC_HOST_DICOM_GDCM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What one file's header says (the elements before its pixel data). A
 * have_* flag is 0 when the element is absent or empty; numbers that do not
 * parse fail the call, naming the element. */
typedef struct lci_dcm_meta {
    char series_uid[72];   /* (0020,000E) */
    char modality[20];     /* (0008,0060) */
    char description[72];  /* (0008,103E) */
    char ts_uid[72];       /* (0002,0010), "" for a file without meta header */
    char ts_name[96];      /* GDCM's name of the syntax, "" when it has none */
    int ts_known;          /* 1: a transfer syntax GDCM 3.0 has a decoder for */
    int encapsulated;      /* 1: compressed (encapsulated pixel data), 0: native */
    char photometric[20];  /* (0028,0004) */
    int rows, cols, frames;                         /* frames: (0028,0008), 1 when absent */
    int bits_allocated, bits_stored, high_bit, pixel_rep, samples;
    int have_ipp, have_iop, have_spacing, have_rescale, have_between, have_thickness;
    double ipp[3];         /* (0020,0032), of the first frame */
    double iop[6];         /* (0020,0037): row direction, column direction */
    double spacing[2];     /* (0028,0030): between rows, between columns */
    double slope, intercept;   /* (0028,1053), (0028,1052); 1 and 0 when absent */
    double between;        /* (0018,0088) spacing between slices */
    double thickness;      /* (0018,0050) */
    int instance;          /* (0020,0013), 0 when absent */
    /* multi-frame: per-frame positions from the per-frame functional groups
     * (5200,9230) (frames x 3, malloc'd; NULL when not given), or frame
     * offsets along the normal from (3004,000C) (frames, malloc'd; NULL) */
    double *frame_ipp;
    double *frame_offset;
    /* enhanced multi-frame: each frame's Rescale Slope and Intercept from its
     * Pixel Value Transformation (0028,9145) in the per-frame functional
     * groups (frames x 2, malloc'd; NULL when they give none: then slope and
     * intercept above hold for every frame; else those are frame 0's) */
    double *frame_rescale;
} lci_dcm_meta;

/* Reads path's header up to its pixel data into m (zeroed first). */
int lci_gdcm_header(const char *path, lci_dcm_meta *m, char *err, size_t errlen);
/* Decodes path's pixel data (any transfer syntax GDCM decodes) into dst,
 * which holds exactly `bytes`: the stored values of every frame, as
 * bits_allocated-bit little-endian words. A decoded length other than
 * `bytes` fails. */
int lci_gdcm_pixels(const char *path, void *dst, size_t bytes, char *err, size_t errlen);
/* GDCM's version, e.g. "3.0.21". */
const char *lci_gdcm_version(void);

#ifdef __cplusplus
}
#endif

#endif
