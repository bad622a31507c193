/* The nearest axis-aligned frame of a voxel-to-world matrix (orient.h),
 * shared by the NIfTI and DICOM readers. The permutation of the six that
 * puts the most of each voxel axis onto a world axis wins; its flips follow
 * the signs of those components. */
#include <math.h>
#include <string.h>
#include "host/formats/orient.h"

double lci_axis_frame(const double m[3][4], const int64_t n[3], int perm[3], int flip[3], double spacing[3],
                      double origin[3])
{
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    double norm[3];
    for (int a = 0; a < 3; a++) {
        norm[a] = sqrt(m[0][a] * m[0][a] + m[1][a] * m[1][a] + m[2][a] * m[2][a]);
        if (!(norm[a] > 0.0)) norm[a] = 1.0;
    }
    double best = -1.0;
    int bp = 0;
    for (int p = 0; p < 6; p++) {
        double score = 0.0;
        for (int w = 0; w < 3; w++) score += fabs(m[w][perms[p][w]]) / norm[perms[p][w]];
        if (score > best + 1e-12) best = score, bp = p;
    }
    double worst = 1.0; /* smallest cosine */
    int exact = 1;
    for (int w = 0; w < 3; w++) {
        int a = perm[w] = perms[bp][w];
        flip[w] = m[w][a] < 0.0;
        spacing[w] = norm[a];
        double c = fabs(m[w][a]) / norm[a];
        worst = c < worst ? c : worst;
        for (int v = 0; v < 3; v++)
            if (v != w && fabs(m[v][a]) > 1e-6 * norm[a]) exact = 0;
    }
    for (int w = 0; w < 3; w++) {
        int a = perm[w];
        if (exact) origin[w] = m[w][3] + (flip[w] ? (double)(n[a] - 1) * m[w][a] : 0.0);
        else { /* keep the centre */
            double c = m[w][3];
            for (int b = 0; b < 3; b++) c += m[w][b] * 0.5 * (double)(n[b] - 1);
            origin[w] = c - 0.5 * (double)(n[a] - 1) * spacing[w];
        }
    }
    return exact ? 0.0 : acos(fmin(1.0, worst)) * 180.0 / M_PI;
}

void lci_axis_reorder(const void *src, void *dst, int es, const int64_t n[3], const int perm[3], const int flip[3])
{
    uint64_t stride[3] = {1, (uint64_t)n[0], (uint64_t)n[0] * (uint64_t)n[1]};
    int64_t on[3] = {n[perm[0]], n[perm[1]], n[perm[2]]};
    uint64_t o_i = 0;
    for (int64_t w2 = 0; w2 < on[2]; w2++)
        for (int64_t w1 = 0; w1 < on[1]; w1++) {
            uint64_t base = (uint64_t)(flip[1] ? on[1] - 1 - w1 : w1) * stride[perm[1]] +
                            (uint64_t)(flip[2] ? on[2] - 1 - w2 : w2) * stride[perm[2]];
            uint64_t s0 = stride[perm[0]];
            for (int64_t w0 = 0; w0 < on[0]; w0++, o_i++) {
                uint64_t si = base + (uint64_t)(flip[0] ? on[0] - 1 - w0 : w0) * s0;
                memcpy((char *)dst + o_i * (uint64_t)es, (const char *)src + si * (uint64_t)es, (size_t)es);
            }
        }
}
