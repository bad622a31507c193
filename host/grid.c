/* Structured grids: not built yet (issue 4). */
#include "scene.h"

lc_status lci_grid_info(lc_device *dev, const lc_grid *g, const lc_render_desc *desc, lci_scene_info *out)
{
    (void)g, (void)desc, (void)out;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "structured grids are not implemented yet");
}

lc_status lci_grid_prepare(lc_device *dev, const lc_grid *g, const lc_render_desc *desc, const lc_kframe *frame,
                           lci_prepared *out)
{
    (void)g, (void)desc, (void)frame, (void)out;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "structured grids are not implemented yet");
}
