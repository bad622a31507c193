/* The projection kernels of a target (kernels/sph_project.h), picked as the
 * device's kernel table is (host/exec/cpu.c). */
#ifndef LC_SPH_PROJECT_H
#define LC_SPH_PROJECT_H

#include "lanecast/lanecast.h"
#include "kernels/sph_project.h"

/* NULL if the target is not compiled in. */
const lc_kproj *lci_project_kernels(lc_target target);

#endif
