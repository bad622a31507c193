/* How the coherent particle kernel runs a frame (host/kinds/particles_frame.c):
 * its pass buffer, group and tile sides, and the knobs tests and A/B runs
 * set through the environment. Shared by the particle kind and RBF sets'
 * coherent method, which runs the same kernel. */
#ifndef LCI_PARTICLES_FRAME_H
#define LCI_PARTICLES_FRAME_H

#include <stdint.h>
#include "lanecast/lanecast.h"
#include "kernels/shared/kframe.h"
#include "kernels/shared/kparticles.h"

/* k's buffer_adapt and buffer_k (from buffer_samples, 0 = adapt), group list
 * capacity and the eye_generic and cone_off knobs, for nfields fields. */
void lci_pcoherent_settings(lc_kparticles *k, int nfields, int32_t buffer_samples);

/* LANECAST_PARTICLE_CONE=0: no per-vector cone pre-test (same image, bit for bit). */
int32_t lci_pcone_off(void);

/* Rays per group side for a render whose packet is 0 (0 otherwise: the
 * desc's packet), on a target of this many lanes. */
int32_t lci_pgroup_side(const lc_render_desc *d, int lanes);

/* The tile side in pixels the kind asks for when the desc leaves tile at 0
 * (0: the host's 32), for k's group side; coherent: the coherent method. */
int lci_ptile_side(const lc_kframe *f, const lc_kparticles *k, int coherent);

#endif
