/* Operation codes for the lane probe (kernels/lane_probe.c): the conformance
 * suite drives every lane operation of every target through one entry point
 * and compares against the scalar target. Plain C, shared with the host. */
#ifndef LC_LANE_OPS_H
#define LC_LANE_OPS_H

enum lc_lane_op {
    LC_OP_ADD, LC_OP_SUB, LC_OP_MUL, LC_OP_DIV, LC_OP_MIN, LC_OP_MAX, LC_OP_ABS, LC_OP_NEG,
    LC_OP_SQRT, LC_OP_FMA, LC_OP_FMS, LC_OP_FNMA, LC_OP_RCP, LC_OP_RSQRT, LC_OP_FLOOR,
    LC_OP_EXP, LC_OP_POWI, LC_OP_SCALE2, LC_OP_CLAMP, LC_OP_LERP,
    LC_OP_TO_VI, LC_OP_VI_TO_VF, LC_OP_AS_VI_ROUNDTRIP,
    LC_OP_LT, LC_OP_LE, LC_OP_GT, LC_OP_GE, LC_OP_EQ, LC_OP_NE,
    LC_OP_SELECT, LC_OP_VI_ADD, LC_OP_VI_SUB, LC_OP_VI_MUL, LC_OP_VI_MIN, LC_OP_VI_MAX,
    LC_OP_VI_AND, LC_OP_VI_OR, LC_OP_VI_SLL, LC_OP_VI_SRL,
    LC_OP_VI_LT, LC_OP_VI_GT, LC_OP_VI_EQ, LC_OP_VI_SELECT,
    LC_OP_MASK_AND, LC_OP_MASK_OR, LC_OP_MASK_XOR, LC_OP_MASK_ANDNOT, LC_OP_MASK_NOT,
    LC_OP_LOAD_MASKED, LC_OP_STORE_MASKED, LC_OP_GATHER, LC_OP_GATHER_MASKED, LC_OP_VI_GATHER,
    LC_OP_GATHER_U8, LC_OP_GATHER_U16, LC_OP_GATHER_U8PAIR, LC_OP_GATHER_U16PAIR,
    LC_OP_LANE, LC_OP_IOTA, LC_OP_BITS_ROUNDTRIP, LC_OP_FIRST_N,
    /* horizontal: one result per chunk of lane-width elements, in out[chunk] */
    LC_OP_ANY, LC_OP_ALL, LC_OP_NONE, LC_OP_POPCNT, LC_OP_FIRST, LC_OP_BITS,
    LC_OP_REDUCE_ADD, LC_OP_REDUCE_MIN, LC_OP_REDUCE_MAX, LC_OP_REDUCE_MIN_MASKED,
    LC_OP_COUNT
};

/* Arguments of one probe call. Arrays hold n elements, n a multiple of 16.
 * a, b, c: float operands; ia, ib: int operands; mk: mask (lane active where
 * mk[i] > 0); out/iout: results. For GATHER the table is a (gsize floats) and
 * the indices are ia. The narrow gathers (GATHER_U8 ... U16PAIR, unmasked in
 * the vocabulary) read ib's 4n bytes as a little-endian uint8 or uint16 table
 * at indices ia; they may load up to 3 bytes past the addressed element, so
 * the suite keeps indices at most 4n - 4 (u8, u8 pairs) or 2n - 2 (u16,
 * u16 pairs), the last element that leaves those bytes inside ib. */
typedef struct lc_lane_args {
    int op;
    int n;
    const float *a, *b, *c;
    const int32_t *ia, *ib, *mk;
    float *out;
    int32_t *iout;
} lc_lane_args;

#endif
