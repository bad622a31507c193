/* Particles: not built yet (issue 3). */
#include "scene.h"

lc_status lci_particles_info(lc_device *dev, const lc_particles *g, const lc_render_desc *desc, lci_scene_info *out)
{
    (void)g, (void)desc, (void)out;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "particles are not implemented yet");
}

lc_status lci_particles_prepare(lc_device *dev, const lc_particles *g, const lc_render_desc *desc, const lc_kframe *frame,
                           lci_prepared *out)
{
    (void)g, (void)desc, (void)frame, (void)out;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "particles are not implemented yet");
}
