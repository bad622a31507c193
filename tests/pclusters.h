/* The clustered particle scene of the particle kernel tests
 * (test_particles_group, test_particles_passes, test_particles_skip): three
 * clusters of ncl particles each around the centres cc, then nbg particles
 * uniform in [0, 10)^3. Per particle, in this order from one xorshift
 * stream: the radius r0 + rw u, the value 0.5 + u (skipped when val is
 * NULL), the position (cluster: centre + spread (u + u + u - 1.5) per axis);
 * field i % 2. */
#ifndef LC_TEST_PCLUSTERS_H
#define LC_TEST_PCLUSTERS_H

#include <stdint.h>

static inline float pclusters_urand(uint64_t *rs)
{
    *rs ^= *rs << 13, *rs ^= *rs >> 7, *rs ^= *rs << 17;
    return (float)(*rs >> 40) / 16777216.0f;
}

static inline void pclusters_make(uint64_t seed, int ncl, int nbg, const float cc[3][3], float spread, float r0,
                                  float rw, float *xyz, float *rad, float *val, uint8_t *fid)
{
    uint64_t rs = seed;
    for (int i = 0; i < 3 * ncl + nbg; i++) {
        rad[i] = r0 + rw * pclusters_urand(&rs);
        if (val) val[i] = 0.5f + pclusters_urand(&rs);
        fid[i] = (uint8_t)(i % 2);
        for (int a = 0; a < 3; a++) {
            if (i >= 3 * ncl) {
                xyz[3 * i + a] = 10.0f * pclusters_urand(&rs);
            } else {
                float u = pclusters_urand(&rs) + pclusters_urand(&rs) + pclusters_urand(&rs);
                xyz[3 * i + a] = cc[i / ncl][a] + spread * (u - 1.5f);
            }
        }
    }
}

#endif
