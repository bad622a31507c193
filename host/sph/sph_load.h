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
    int normalise;       /* option normalise = 0|1: the loader also emits the m_i / rho_i
                            (lc_particles_desc.norm_weights) */
} lci_sph_opts;

/* The three options from the reader's arguments; bad values fail naming the option. */
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

/* w[i] = m_i / rho_i (the normalised interpolant's weights; rho checked by lci_sph_weigh first). */
void lci_sph_norm_weights(int64_t n, const float *m, double m_const, const float *rho, float *w);

/* With the option normalise = 1, hands w (count floats, malloc'ed; NULL
 * when the option is off) to the loaded desc as its norm_weights. */
void lci_sph_keep_norm(lci_loaded *out, float *w);

/* The option value = NAME, NAME:K (component K of an N x C block or dataset)
 * or |NAME| (the magnitude of its rows), for any per-particle block. */
#define LCI_VALUE_MAG (-2)
typedef struct lci_value_spec {
    char name[96]; /* the block label or dataset path (inside the PartTypeN group) */
    int comp;      /* -1: one value per particle; K >= 0: component K; LCI_VALUE_MAG: the magnitude */
} lci_value_spec;

/* 0, or -1 when text is empty, too long or has an empty name or a bad component. */
int lci_value_spec_parse(const char *text, lci_value_spec *v);

/* out[i] from n rows of c values (in, row-major) as v says; in may be out
 * when c == 1. The caller checked the component against c. */
void lci_value_spec_reduce(const lci_value_spec *v, const float *in, int64_t n, int c, float *out);

/* The loaded particles' radius note (lc_particles_desc.radius_note), printf-style, kept with out. */
void lci_sph_note(lci_loaded *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
