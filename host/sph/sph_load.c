/* The SPH snapshot readers' shared options and conversions (sph_load.h). */
#include <math.h>
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
    if ((x = lci_option_find(a, "normalise"))) {
        lc_status s = lci_option_int(dev, a->path, x, 0, 1, &o->normalise);
        if (s != LC_OK) return s;
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

void lci_sph_norm_weights(int64_t n, const float *m, double m_const, const float *rho, float *w)
{
    for (int64_t i = 0; i < n; i++) w[i] = (float)((m ? (double)m[i] : m_const) / (double)rho[i]);
}

void lci_sph_keep_norm(lci_loaded *out, float *w)
{
    if (!w) return;
    if (lci_loaded_keep(out, w)) ((lc_particles_desc *)out->desc)->norm_weights = w;
}

int lci_value_spec_parse(const char *text, lci_value_spec *v)
{
    memset(v, 0, sizeof *v);
    v->comp = -1;
    size_t n = strlen(text);
    if (n == 0 || n >= sizeof v->name) return -1;
    if (text[0] == '|') {
        if (n < 3 || text[n - 1] != '|') return -1;
        memcpy(v->name, text + 1, n - 2);
        v->comp = LCI_VALUE_MAG;
        return strchr(v->name, '|') || strchr(v->name, ':') ? -1 : 0;
    }
    const char *c = strrchr(text, ':');
    if (!c) return memcpy(v->name, text, n), 0;
    char *end;
    long k = strtol(c + 1, &end, 10);
    if (c == text || !c[1] || *end || k < 0 || k > 1023) return -1;
    memcpy(v->name, text, (size_t)(c - text));
    v->comp = (int)k;
    return strchr(v->name, '|') ? -1 : 0;
}

void lci_value_spec_reduce(const lci_value_spec *v, const float *in, int64_t n, int c, float *out)
{
    for (int64_t i = 0; i < n; i++) {
        const float *row = in + (size_t)i * (size_t)c;
        if (v->comp == LCI_VALUE_MAG) {
            double q = 0.0;
            for (int j = 0; j < c; j++) q += (double)row[j] * (double)row[j];
            out[i] = (float)sqrt(q);
        } else
            out[i] = row[v->comp >= 0 ? v->comp : 0];
    }
}
