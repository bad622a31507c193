/* The SPH snapshot readers' shared options and conversions (sph_load.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/internal.h"
#include "host/sph/sph_kernel.h"
#include "host/sph/sph_load.h"

lc_status lci_sph_opts_parse(lc_device *dev, const lci_read_args *a, lci_sph_opts *o)
{
    memset(o, 0, sizeof *o);
    const lc_option *x;
    if ((x = lci_option_find(a, "kernel")) && lc_kernel_from_name(x->value, &o->kernel) != LC_OK)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: option kernel = '%s', expected gaussian, m4, m5, m6, wendland-c2, wendland-c4 or "
                         "wendland-c6", a->path, x->value);
    if ((x = lci_option_find(a, "hsml_is"))) {
        if (!strcmp(x->value, "h")) o->hsml_is = LCI_HSML_SMALL_H;
        else if (!strcmp(x->value, "H")) o->hsml_is = LCI_HSML_BIG_H;
        else
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: option hsml_is = '%s', expected h (the code's smoothing length, H = gamma h) or H "
                             "(the kernel's support radius)", a->path, x->value);
    }
    return LC_OK;
}

lc_kernel lci_sph_gamma_kernel(const lci_sph_opts *o, lc_kernel file_kernel, const char **why)
{
    if (o->kernel != LC_KERNEL_GAUSSIAN) return *why = "the kernel rendered", o->kernel;
    if (file_kernel != LC_KERNEL_GAUSSIAN) return *why = "the kernel the file records", file_kernel;
    return *why = "no kernel named or recorded: the cubic spline's", LC_KERNEL_M4;
}

lc_status lci_sph_weigh(lc_device *dev, const char *path, const char *what, int64_t first, int64_t n, const float *m,
                        double m_const, const float *rho, float *v)
{
    for (int64_t i = 0; i < n; i++) {
        if (!(rho[i] > 0.0f))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: particle %lld has density %g; SPH weights m / rho need > 0",
                             path, what, (long long)(first + i), (double)rho[i]);
        double mi = m ? (double)m[i] : m_const;
        v[i] = (float)(mi / (double)rho[i] * (double)v[i]);
    }
    return LC_OK;
}

void lci_sph_note(lci_loaded *out, const char *fmt, ...)
{
    char *b = malloc(256);
    if (!b) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(b, 256, fmt, ap);
    va_end(ap);
    if (lci_loaded_keep(out, b)) ((lc_particles_desc *)out->desc)->radius_note = b;
}
