/* The uniform/varying lane vocabulary. One backend header per target defines
 * vfloat/vint/vmask and the vf_/vi_/vm_ operations with identical semantics;
 * lane_math.h builds exp and friends on top of them, once for all targets.
 *
 * The target is chosen by exactly one LC_TARGET_* macro (set by meson per
 * kernel library). Plain C types are uniform; vfloat/vint/vmask are varying. */
#ifndef LC_LANE_H
#define LC_LANE_H

#include <stddef.h>
#include <stdint.h>

#if defined(LC_TARGET_SCALAR)
#include "lane_scalar.h"
#elif defined(LC_TARGET_SSE4)
#include "lane_sse4.h"
#elif defined(LC_TARGET_AVX2)
#include "lane_avx2.h"
#elif defined(LC_TARGET_AVX512)
#include "lane_avx512.h"
#elif defined(LC_TARGET_AVX512_8)
#include "lane_avx512_8.h"
#else
#error "lane.h: define one of LC_TARGET_SCALAR, LC_TARGET_SSE4, LC_TARGET_AVX2, LC_TARGET_AVX512, LC_TARGET_AVX512_8"
#endif

#include "lane_math.h"

#endif
