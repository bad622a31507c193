/* Lane probe: applies one lane operation over arrays, chunk by chunk, so the
 * conformance suite can compare every target with the scalar one. Compiled
 * once per target. */
#include "lane/lane.h"
#include "kernels.h"

static inline vmask load_mask(const int32_t *mk) { return vi_gt(vi_load(mk), vi_set1(0)); }
static inline vfloat mask_to_vf(vmask m) { return vf_select(m, vf_set1(1.0f), vf_zero()); }

void LC_KFN(lc_lane_apply)(const lc_lane_args *g)
{
    for (int i = 0, chunk = 0; i < g->n; i += LC_W, chunk++) {
        vfloat a = vf_load(g->a + i), b = vf_load(g->b + i), c = vf_load(g->c + i);
        vint ia = vi_load(g->ia + i), ib = vi_load(g->ib + i);
        vmask m = load_mask(g->mk + i);
        vmask ma = vf_gt(a, vf_zero()), mb = vf_gt(b, vf_zero());
        float *o = g->out + i;
        int32_t *io = g->iout + i;
        switch (g->op) {
        case LC_OP_ADD: vf_store(o, vf_add(a, b)); break;
        case LC_OP_SUB: vf_store(o, vf_sub(a, b)); break;
        case LC_OP_MUL: vf_store(o, vf_mul(a, b)); break;
        case LC_OP_DIV: vf_store(o, vf_div(a, b)); break;
        case LC_OP_MIN: vf_store(o, vf_min(a, b)); break;
        case LC_OP_MAX: vf_store(o, vf_max(a, b)); break;
        case LC_OP_ABS: vf_store(o, vf_abs(a)); break;
        case LC_OP_NEG: vf_store(o, vf_neg(a)); break;
        case LC_OP_SQRT: vf_store(o, vf_sqrt(vf_abs(a))); break;
        case LC_OP_FMA: vf_store(o, vf_fma(a, b, c)); break;
        case LC_OP_FMS: vf_store(o, vf_fms(a, b, c)); break;
        case LC_OP_FNMA: vf_store(o, vf_fnma(a, b, c)); break;
        case LC_OP_RCP: vf_store(o, vf_rcp(a)); break;
        case LC_OP_RSQRT: vf_store(o, vf_rsqrt(vf_abs(a))); break;
        case LC_OP_FLOOR: vf_store(o, vf_floor(a)); break;
        case LC_OP_EXP: vf_store(o, vf_exp(a)); break;
        case LC_OP_POWI: vf_store(o, vf_powi(a, 16)); break;
        case LC_OP_SCALE2: vf_store(o, vf_scale2(a, vi_to_vf(ia))); break;
        case LC_OP_CLAMP: vf_store(o, vf_clamp(a, vf_min(b, c), vf_max(b, c))); break;
        case LC_OP_LERP: vf_store(o, vf_lerp(a, b, c)); break;
        case LC_OP_TO_VI: vi_store(io, vf_to_vi(a)); break;
        case LC_OP_VI_TO_VF: vf_store(o, vi_to_vf(ia)); break;
        case LC_OP_AS_VI_ROUNDTRIP: vf_store(o, vi_as_vf(vf_as_vi(a))); break;
        case LC_OP_LT: vf_store(o, mask_to_vf(vf_lt(a, b))); break;
        case LC_OP_LE: vf_store(o, mask_to_vf(vf_le(a, b))); break;
        case LC_OP_GT: vf_store(o, mask_to_vf(vf_gt(a, b))); break;
        case LC_OP_GE: vf_store(o, mask_to_vf(vf_ge(a, b))); break;
        case LC_OP_EQ: vf_store(o, mask_to_vf(vf_eq(a, b))); break;
        case LC_OP_NE: vf_store(o, mask_to_vf(vf_ne(a, b))); break;
        case LC_OP_SELECT: vf_store(o, vf_select(m, a, b)); break;
        case LC_OP_VI_ADD: vi_store(io, vi_add(ia, ib)); break;
        case LC_OP_VI_SUB: vi_store(io, vi_sub(ia, ib)); break;
        case LC_OP_VI_MUL: vi_store(io, vi_mul(ia, ib)); break;
        case LC_OP_VI_MIN: vi_store(io, vi_min(ia, ib)); break;
        case LC_OP_VI_MAX: vi_store(io, vi_max(ia, ib)); break;
        case LC_OP_VI_AND: vi_store(io, vi_and(ia, ib)); break;
        case LC_OP_VI_OR: vi_store(io, vi_or(ia, ib)); break;
        case LC_OP_VI_SLL: vi_store(io, vi_sll(ia, 3)); break;
        case LC_OP_VI_SRL: vi_store(io, vi_srl(ia, 5)); break;
        case LC_OP_VI_LT: vf_store(o, mask_to_vf(vi_lt(ia, ib))); break;
        case LC_OP_VI_GT: vf_store(o, mask_to_vf(vi_gt(ia, ib))); break;
        case LC_OP_VI_EQ: vf_store(o, mask_to_vf(vi_eq(ia, ib))); break;
        case LC_OP_VI_SELECT: vi_store(io, vi_select(m, ia, ib)); break;
        case LC_OP_MASK_AND: vf_store(o, mask_to_vf(vm_and(ma, mb))); break;
        case LC_OP_MASK_OR: vf_store(o, mask_to_vf(vm_or(ma, mb))); break;
        case LC_OP_MASK_XOR: vf_store(o, mask_to_vf(vm_xor(ma, mb))); break;
        case LC_OP_MASK_ANDNOT: vf_store(o, mask_to_vf(vm_andnot(ma, mb))); break;
        case LC_OP_MASK_NOT: vf_store(o, mask_to_vf(vm_not(ma))); break;
        case LC_OP_LOAD_MASKED: vf_store(o, vf_load_masked(m, g->a + i, b)); break;
        case LC_OP_STORE_MASKED: vf_store(o, c); vf_store_masked(m, o, a); break;
        case LC_OP_GATHER: vf_store(o, vf_gather(g->a, ia)); break;
        case LC_OP_GATHER_MASKED: vf_store(o, vf_gather_masked(m, g->a, ia, b)); break;
        case LC_OP_VI_GATHER: vi_store(io, vi_gather(g->ib, ia)); break;
        case LC_OP_GATHER_U8: vi_store(io, vi_gather_u8((const uint8_t *)(const void *)g->ib, ia)); break;
        case LC_OP_GATHER_U16: vi_store(io, vi_gather_u16((const uint16_t *)(const void *)g->ib, ia)); break;
        case LC_OP_GATHER_U8PAIR: vi_store(io, vi_gather_u8pair((const uint8_t *)(const void *)g->ib, ia)); break;
        case LC_OP_GATHER_U16PAIR: vi_store(io, vi_gather_u16pair((const uint16_t *)(const void *)g->ib, ia)); break;
        case LC_OP_LANE:
            for (int l = 0; l < LC_W; l++) { o[l] = vf_lane(a, l); io[l] = vi_lane(ia, l); }
            break;
        case LC_OP_IOTA: vf_store(o, vf_iota()); vi_store(io, vi_iota()); break;
        case LC_OP_BITS_ROUNDTRIP: vf_store(o, mask_to_vf(vm_from_bits(vm_bits(m)))); break;
        case LC_OP_FIRST_N: vf_store(o, mask_to_vf(vm_first_n(g->ia[i]))); break;
        case LC_OP_ANY: g->out[chunk] = (float)vm_any(m); break;
        case LC_OP_ALL: g->out[chunk] = (float)vm_all(m); break;
        case LC_OP_NONE: g->out[chunk] = (float)vm_none(m); break;
        case LC_OP_POPCNT: g->out[chunk] = (float)vm_popcnt(m); break;
        case LC_OP_FIRST: g->out[chunk] = (float)vm_first(m); break;
        case LC_OP_BITS: g->iout[chunk] = (int32_t)vm_bits(m); break;
        case LC_OP_REDUCE_ADD: g->out[chunk] = vf_reduce_add(a); break;
        case LC_OP_REDUCE_MIN: g->out[chunk] = vf_reduce_min(a); break;
        case LC_OP_REDUCE_MAX: g->out[chunk] = vf_reduce_max(a); break;
        case LC_OP_REDUCE_MIN_MASKED: g->out[chunk] = vf_reduce_min_masked(m, a); break;
        default: break;
        }
    }
}
