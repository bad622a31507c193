/* XDR (RFC 4506) values: big-endian 4-byte integers and IEEE floats, 8-byte
 * doubles, as GROMACS's XTC and TRR files hold them. */
#ifndef LC_HOST_XDR_H
#define LC_HOST_XDR_H

#include <stdint.h>
#include <string.h>
#include "host/formats/binfile.h"

/* Makes lci_bin_i32 / lci_bin_fix read big-endian values. */
static inline void lci_xdr_order(lci_bin *b)
{
    int one = 1;
    b->swap = *(unsigned char *)&one == 1;
}

static inline uint32_t lci_xdr_u32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static inline float lci_xdr_f32(const unsigned char *p)
{
    uint32_t u = lci_xdr_u32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static inline double lci_xdr_f64(const unsigned char *p)
{
    uint64_t u = (uint64_t)lci_xdr_u32(p) << 32 | lci_xdr_u32(p + 4);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

#endif
