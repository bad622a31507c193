/* Particles deposited to grid nodes (lc_particles_resample, issue 28), one
 * brick at a time, particle-major: for each particle the box of the brick's
 * nodes its support reaches, then rows along x.
 *
 * The Gaussian is separable, exp(nir (dx^2 + dy^2 + dz^2)) = ex ey ez, so a
 * particle costs one exp per node of its box's three edges (rows of factors
 * computed in lanes) and a multiply-add per node: no exp along the rows.
 * The support test is the particle renderer's, d^2 < (sigma r)^2 with
 * d^2 = dx^2 + (dy^2 + dz^2) in its order (particles_common.h sample_d2),
 * the offsets exact to a float's rounding (axis_rows). The SPH kernels are not separable: their rows take
 * particles_sph.h's sph_term over the lanes, the renderer's own evaluation.
 * Lanes run along x; a row's vectors that lie inside the brick are loaded and
 * stored whole (the brick's nodes are this worker's alone), those that cross
 * its x edge through masks. */
#include "kernels.h"
#include "particles_sph.h"
#include "shared/kresample.h"

/* Squared offsets of nodes i0 .. i0 + n - 1 from c along an axis (whole
 * vectors: up to LC_W - 1 entries past n, which rows read on lanes they mask
 * off), and with e their Gaussian factors exp(nir d^2). The offsets are
 * taken in double (node o + i sp exactly, then minus c) and rounded once: a
 * float node position is off by an ulp of its coordinate, which near the
 * edge of an SPH kernel's support (f ~ (1 - u)^3) is a relative error of
 * several 1e-5 in a term; per particle these are a few dozen scalar
 * operations against the multiply-adds of its nodes. */
static inline void axis_rows(float o, float sp, int64_t i0, int64_t n, float c, float nir, float *d2, float *e)
{
    for (int64_t m = 0; m < n; m++) {
        double d = ((double)o + (double)(i0 + m) * (double)sp) - (double)c;
        d2[m] = (float)(d * d);
    }
    if (e)
        for (int64_t m = 0; m < n; m += LC_W) vf_store(e + m, vf_exp(vf_mul(vf_load(d2 + m), vf_set1(nir))));
}

/* Adds t on the lanes of `in` to row[i .. i + LC_W); whole vectors when they
 * lie inside the brick's x range (ending at xend). */
static inline void row_add(float *row, int64_t i, int64_t xend, vmask in, vfloat t)
{
    if (i + LC_W <= xend) {
        vf_store(row + i, vf_add(vf_load(row + i), vf_select(in, t, vf_zero())));
    } else {
        vf_store_masked(in, row + i, vf_add(vf_load_masked(in, row + i, vf_zero()), t));
    }
}

/* The chord of a row: nodes [*a, *b] of [x0, x1] within sqrt(rem) of cx
 * (one node generous on each side, so a reciprocal of the spacing, inv,
 * serves: the d^2 test decides). */
static inline void chord(float ox, double inv, float cx, float rem, int64_t x0, int64_t x1, int64_t *a, int64_t *b)
{
    double half = sqrtf(rem), u = ((double)cx - (double)ox) * inv;
    double lo = floor(u - half * inv) - 1.0, hi = ceil(u + half * inv) + 1.0;
    *a = lo > (double)x0 ? (int64_t)lo : x0;
    *b = hi < (double)x1 ? (int64_t)hi : x1;
}

void LC_KFN(lc_resample_brick)(const lc_kresample *s, lc_kresample_brick *b)
{
    const int sph = s->kernel != LC_KSPH_GAUSSIAN;
    const int64_t nx = s->size[0], ny = s->size[1];
    int64_t side = b->hi[0] - b->lo[0];
    for (int a = 1; a < 3; a++) side = b->hi[a] - b->lo[a] > side ? b->hi[a] - b->lo[a] : side;
    float *x2 = b->scratch, *ex = x2 + side + 32, *y2 = ex + side + 32, *ey = y2 + side + 32;
    float *z2 = ey + side + 32, *ez = z2 + side + 32;
    uint64_t evals = 0;
    const double inv = 1.0 / (double)s->spacing[0];
    for (int64_t l = 0; l < b->n; l++) {
        uint32_t p = b->list[l];
        float c[3] = {s->px[p], s->py[p], s->pz[p]}, r = s->r[p];
        float kk = s->kappa * s->k[p];
        float R = sph ? r : s->sigma * r, R2 = R * R;
        int64_t i0[3], i1[3];
        int reach = 1;
        for (int a = 0; a < 3 && reach; a++)
            reach = lc_kresample_range(s->origin[a], s->spacing[a], b->lo[a], b->hi[a], c[a], R, &i0[a], &i1[a]);
        if (!reach) continue;
        float nir = sph ? 0.0f : -1.0f / (2.0f * r * r); /* host/kinds/particles.c's neg_inv_2r2 */
        axis_rows(s->origin[0], s->spacing[0], i0[0], i1[0] - i0[0] + 1, c[0], nir, x2, sph ? NULL : ex);
        axis_rows(s->origin[1], s->spacing[1], i0[1], i1[1] - i0[1] + 1, c[1], nir, y2, sph ? NULL : ey);
        axis_rows(s->origin[2], s->spacing[2], i0[2], i1[2] - i0[2] + 1, c[2], nir, z2, sph ? NULL : ez);
        sph_consts sc = sph_consts_make(r, kk, s->knorm);
        vfloat vR2 = vf_set1(R2);
        for (int64_t z = i0[2]; z <= i1[2]; z++) {
            float dz2 = z2[z - i0[2]];
            if (!(dz2 < R2)) continue;
            for (int64_t y = i0[1]; y <= i1[1]; y++) {
                float dyz2 = y2[y - i0[1]] + dz2;
                if (!(dyz2 < R2)) continue;
                int64_t xa, xb;
                chord(s->origin[0], inv, c[0], R2 - dyz2, i0[0], i1[0], &xa, &xb);
                float *row = s->values + (z * ny + y) * nx;
                vfloat w = sph ? vf_zero() : vf_set1(kk * (ey[y - i0[1]] * ez[z - i0[2]]));
                vfloat vdyz2 = vf_set1(dyz2);
                for (int64_t x = xa; x <= xb; x += LC_W) {
                    vmask in = vm_first_n((int)(xb - x + 1 < LC_W ? xb - x + 1 : LC_W));
                    vfloat d2 = vf_add(vf_load(x2 + (x - i0[0])), vdyz2);
                    in = vm_and(in, vf_lt(d2, vR2));
                    if (vm_none(in)) continue;
                    vfloat t = sph ? sph_term(s->kernel, &sc, d2, in, NULL) : vf_mul(w, vf_load(ex + (x - i0[0])));
                    row_add(row, x, b->hi[0], in, t);
                    evals += (uint64_t)vm_popcnt(in);
                }
            }
        }
    }
    b->evals = evals;
}
