/* The projection kernels per target (kernels/sph_project.c is compiled once
 * per target into meson's kernel libraries, as the ray casters are). */
#include "host/sph/project.h"

const lc_kproj *lci_project_kernels(lc_target target)
{
    switch (target) {
    case LC_TARGET_SCALAR: return &lc_kproj_scalar;
#ifdef LC_HAVE_SSE4
    case LC_TARGET_SSE4: return &lc_kproj_sse4;
#endif
#ifdef LC_HAVE_AVX2
    case LC_TARGET_AVX2: return &lc_kproj_avx2;
#endif
#ifdef LC_HAVE_AVX512
    case LC_TARGET_AVX512: return &lc_kproj_avx512;
#endif
#ifdef LC_HAVE_AVX512_8
    case LC_TARGET_AVX512_8: return &lc_kproj_avx512_8;
#endif
    default: return NULL;
    }
}
