/* The k-nearest-neighbour radii the particle readers use when a file has no
 * radii (host/formats/plist.c, lci_knn_radii) against a brute-force search:
 * the distance to the k-th nearest other particle, bit for bit (both take
 * the same float squared distances). Sets: uniform, clustered with one far
 * outlier (the grid then stretches to 1 x 1 x 1024 cells; the fuzzer found
 * its shell search costing O(s^2) per shell there), all on a plane, all on a
 * line, duplicates, two points, k larger than the set. */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include "check.h"
#include "host/formats/plist.h"

static float brute(const float *xyz, size_t n, size_t i, int k, float *d2)
{
    size_t m = 0;
    for (size_t j = 0; j < n; j++) {
        if (j == i) continue;
        float dx = xyz[3 * j] - xyz[3 * i], dy = xyz[3 * j + 1] - xyz[3 * i + 1], dz = xyz[3 * j + 2] - xyz[3 * i + 2];
        d2[m++] = dx * dx + dy * dy + dz * dz;
    }
    if ((size_t)k > m) k = (int)m;
    /* partial selection: the k smallest */
    for (int a = 0; a < k; a++)
        for (size_t b = (size_t)a + 1; b < m; b++)
            if (d2[b] < d2[a]) {
                float t = d2[a];
                d2[a] = d2[b], d2[b] = t;
            }
    return k > 0 ? sqrtf(d2[k - 1]) : 0.0f;
}

static uint64_t rng = 88172645463325252ull;
static float rnd(void)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (float)(rng >> 40) / 16777216.0f;
}

static void check_set(const char *name, float *xyz, size_t n, int k)
{
    float *r = malloc(n * sizeof *r), *d2 = malloc(n * sizeof *d2);
    int rc = lci_knn_radii(xyz, n, k, r);
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < n && rc == 0; i++)
        if (r[i] != brute(xyz, n, i, k, d2)) bad += !bad ? (first = i, 1) : 1;
    CHECK(rc == 0 && bad == 0, "%s: %zu particles, k = %d: every radius equals the brute-force k-th distance (%zu differ, "
          "first %zu)", name, n, k, bad, first);
    free(r), free(d2);
}

int main(void)
{
    enum { N = 3000 };
    float *p = malloc(3 * N * sizeof *p);
    for (int i = 0; i < 3 * N; i++) p[i] = rnd();
    check_set("uniform", p, N, 16);
    /* clusters, and one particle 1e6 away along z */
    for (int i = 0; i < N; i++)
        for (int a = 0; a < 3; a++) p[3 * i + a] = (float)(i % 7) * 3.0f + 0.1f * rnd();
    p[3 * (N - 1) + 2] = 1e6f;
    check_set("clusters + far outlier", p, N, 16);
    check_set("clusters + far outlier, k = 1", p, N, 1);
    for (int i = 0; i < N; i++) p[3 * i] = rnd(), p[3 * i + 1] = rnd(), p[3 * i + 2] = 5.0f;
    check_set("plane z = 5", p, N, 8);
    for (int i = 0; i < N; i++) p[3 * i] = rnd() * 100.0f, p[3 * i + 1] = p[3 * i + 2] = 0.0f;
    check_set("line", p, N, 4);
    for (int i = 0; i < N; i++) p[3 * i] = (float)(i % 10), p[3 * i + 1] = p[3 * i + 2] = 1.0f;
    check_set("duplicates (10 distinct points)", p, N, 32);
    check_set("two points", p, 2, 16);
    check_set("k above n - 1", p, 12, 64);
    free(p);
    return check_summary("test_knn");
}
