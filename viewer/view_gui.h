// The C++ side of lanecast view: the window (view_gui.cpp) and the ImGui
// panels (view_panels.cpp), both over the C state and actions of view.h.
#ifndef LC_VIEW_GUI_H
#define LC_VIEW_GUI_H

extern "C" {
#include "view.h"
}

// The overlay and the panels of one UI frame (between ImGui::NewFrame and Render).
void view_panels(view_state *v, lc_device *ui_dev);

#endif
