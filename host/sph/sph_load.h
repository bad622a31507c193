/* What the SPH snapshot readers (GADGET, HDF5) share: the load options
 * `kernel` and `hsml_is`, the conversion of a code's smoothing
 * length h into lanecast's support radius H, and SPH interpolation weights
 * k_i = m_i / rho_i A_i (docs/sph_kernels.md). */
#ifndef LC_SPH_LOAD_H
#define LC_SPH_LOAD_H

#include "host/formats/format.h"

typedef enum lci_hsml_is {
    LCI_HSML_FILE = 0, /* the format's own convention (GADGET: H; SWIFT: h) */
    LCI_HSML_SMALL_H,  /* hsml_is = h: H = gamma h */
    LCI_HSML_BIG_H     /* hsml_is = H */
} lci_hsml_is;

typedef struct lci_sph_opts {
    lc_kernel kernel;    /* option kernel = NAME (LC_KERNEL_GAUSSIAN when absent) */
    lci_hsml_is hsml_is; /* option hsml_is = h|H */
} lci_sph_opts;

/* The two options from the reader's arguments; bad values fail naming the option. */
lc_status lci_sph_opts_parse(lc_device *dev, const lci_read_args *a, lci_sph_opts *o);

/* Is value A interpolated (k_i = m_i / rho_i A_i)? Yes for an SPH kernel and
 * a value other than none. */
static inline int lci_sph_weighted(const lci_sph_opts *o, int value_given)
{
    return o->kernel != LC_KERNEL_GAUSSIAN && value_given;
}

/* The kernel whose gamma = H / h converts a file's h: the option's, else the
 * file's own (file_kernel, LC_KERNEL_GAUSSIAN if it records none), else M4
 * (GADGET's and SWIFT's default). *why says which. */
lc_kernel lci_sph_gamma_kernel(const lci_sph_opts *o, lc_kernel file_kernel, const char **why);

/* v[i] = m_i / rho_i * v[i] over n particles (m NULL: every mass is m_const);
 * a density that is not > 0 fails naming the file, the dataset or block and
 * the particle. */
lc_status lci_sph_weigh(lc_device *dev, const char *path, const char *what, int64_t first, int64_t n, const float *m,
                        double m_const, const float *rho, float *v);

/* The loaded particles' radius note (lc_particles_desc.radius_note), printf-style, kept with out. */
void lci_sph_note(lci_loaded *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
