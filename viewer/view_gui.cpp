// The window of lanecast view: GLFW 3, an OpenGL 2.1 context (it works over
// ssh -X, where a GL 3 core context does not) and Dear ImGui with its GLFW and
// OpenGL 2 backends (compiled into Debian's libimgui.a). Input and panels call
// the C actions (view_action.c, view_params.c, view_tfedit.c); this file
// draws and forwards, and never waits for a render.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl2.h>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "view_gui.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace {

// LeakSanitizer: the X11/GLX/Mesa stack keeps allocations to the end and its
// driver is unloaded by then, so they cannot be suppressed by module name; the
// calls into GLFW, ImGui's backends and GL run with leak checking off on this
// thread (every other thread, and lanecast's own work, stay checked).
struct gl_calls {
#if defined(__SANITIZE_ADDRESS__)
    gl_calls() { __lsan_disable(); }
    ~gl_calls() { __lsan_enable(); }
#else
    gl_calls() {}
    ~gl_calls() {}
#endif
};

struct gui {
    view_run *run;
    view_state *v;
    GLFWwindow *win;
    GLuint tex;
    int tex_w, tex_h;
    uint64_t seq;
    std::vector<unsigned char> bytes;
    float ox, oy, sw, sh; // the image's rectangle in window coordinates
    char glfw_error[256];
};

gui G;
std::atomic<int> window_up; // wakes are dropped until the window exists

void on_glfw_error(int code, const char *msg) { std::snprintf(G.glfw_error, sizeof G.glfw_error, "%s (%d)", msg, code); }

// Window coordinates to render-image pixels.
void to_image(double x, double y, double *ix, double *iy)
{
    view_state *v = G.v;
    *ix = (x - G.ox) * v->want.rd.width / (G.sw > 0 ? G.sw : 1);
    *iy = (y - G.oy) * v->want.rd.height / (G.sh > 0 ? G.sh : 1);
}

void on_button(GLFWwindow *w, int button, int action, int mods)
{
    ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);
    view_state *v = G.v;
    if (action == GLFW_RELEASE) {
        view_drag_end(v);
        return;
    }
    if (ImGui::GetIO().WantCaptureMouse) return;
    double x, y, ix, iy;
    glfwGetCursorPos(w, &x, &y);
    to_image(x, y, &ix, &iy);
    if (button == GLFW_MOUSE_BUTTON_LEFT)
        view_drag_begin(v, (mods & GLFW_MOD_SHIFT) ? VIEW_DRAG_PAN : VIEW_DRAG_ORBIT, ix, iy);
    else if (button == GLFW_MOUSE_BUTTON_MIDDLE)
        view_drag_begin(v, VIEW_DRAG_PAN, ix, iy);
}

void on_cursor(GLFWwindow *, double x, double y)
{
    double ix, iy;
    to_image(x, y, &ix, &iy);
    view_drag_move(G.v, ix, iy);
}

void on_scroll(GLFWwindow *w, double dx, double dy)
{
    ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
    if (!ImGui::GetIO().WantCaptureMouse && dy != 0.0) view_wheel(G.v, dy);
}

void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
    if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
    static const struct {
        int key;
        const char *name;
    } keys[] = {{GLFW_KEY_R, "r"}, {GLFW_KEY_S, "s"}, {GLFW_KEY_C, "c"},     {GLFW_KEY_H, "h"},
                {GLFW_KEY_B, "b"}, {GLFW_KEY_Q, "q"}, {GLFW_KEY_ESCAPE, "escape"}};
    for (const auto &k : keys)
        if (k.key == key) view_key(G.v, k.name);
}

// The newest pass as an 8-bit texture: C + (1 - A) background, as lc_image_write composites.
void upload()
{
    view_state *v = G.v;
    pthread_mutex_lock(&v->mu);
    if (v->shown.seq == G.seq || !v->shown.rgba) {
        pthread_mutex_unlock(&v->mu);
        return;
    }
    G.seq = v->shown.seq;
    int w = v->shown.width, h = v->shown.height;
    G.bytes.resize((size_t)w * h * 4);
    const float *p = v->shown.rgba;
    const float bg[3] = {v->background.x, v->background.y, v->background.z};
    // round half up by + 0.5 and truncation (the values are >= 0): a loop the compiler
    // vectorises, where std::lround per channel took 7 % of a 1M-particle navigation
    // (perf, docs/bench/view.md) while holding the mutex the render thread publishes under
    unsigned char *b = G.bytes.data();
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const float a = 1.0f - p[4 * i + 3];
        for (int c = 0; c < 3; c++) {
            float x = p[4 * i + c] + a * bg[c];
            x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
            b[4 * i + c] = (unsigned char)(int)(255.0f * x + 0.5f);
        }
        b[4 * i + 3] = 255;
    }
    pthread_mutex_unlock(&v->mu);
    glBindTexture(GL_TEXTURE_2D, G.tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, G.bytes.data());
    G.tex_w = w, G.tex_h = h;
}

// The data's box through the camera, in the image's viewport (fixed function).
void draw_box(int fbw, int fbh, float fscale)
{
    view_state *v = G.v;
    const lc_camera &c = v->want.rd.camera;
    float aspect = (float)v->want.rd.width / (float)v->want.rd.height;
    glViewport((int)(G.ox * fscale), (int)(fbh - (G.oy + G.sh) * fscale), (int)(G.sw * fscale), (int)(G.sh * fscale));
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    lc_vec3 d = {c.at.x - c.eye.x, c.at.y - c.eye.y, c.at.z - c.eye.z};
    float dist = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    if (c.projection == LC_ORTHOGRAPHIC) {
        float hh = 0.5f * (c.height > 0 ? c.height : dist);
        glOrtho(-hh * aspect, hh * aspect, -hh, hh, 1e-3 * dist, 100.0 * dist);
    } else {
        float t = std::tan(0.5f * (c.fovy > 0 ? c.fovy : 40.0f) * 3.14159265f / 180.0f) * 1e-3f * dist;
        glFrustum(-t * aspect, t * aspect, -t, t, 1e-3 * dist, 100.0 * dist);
    }
    // look-at: the rows of the camera basis, then the eye's translation
    lc_vec3 f = {d.x / dist, d.y / dist, d.z / dist}, up = c.up;
    if (up.x == 0 && up.y == 0 && up.z == 0) up.y = 1;
    lc_vec3 s = {f.y * up.z - f.z * up.y, f.z * up.x - f.x * up.z, f.x * up.y - f.y * up.x};
    float sn = std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    if (!(sn > 0)) return;
    s = {s.x / sn, s.y / sn, s.z / sn};
    lc_vec3 u = {s.y * f.z - s.z * f.y, s.z * f.x - s.x * f.z, s.x * f.y - s.y * f.x};
    const float m[16] = {s.x, u.x, -f.x, 0, s.y, u.y, -f.y, 0, s.z, u.z, -f.z, 0, 0, 0, 0, 1};
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(m);
    glTranslatef(-c.eye.x, -c.eye.y, -c.eye.z);
    const lc_vec3 lo = v->vinfo.bounds.lo, hi = v->vinfo.bounds.hi;
    glDisable(GL_TEXTURE_2D);
    glColor3f(0.9f, 0.9f, 0.3f);
    glBegin(GL_LINES);
    for (int e = 0; e < 12; e++) { // 12 edges: axis e / 4, the other two bits from e % 4
        int axis = e / 4, a = e & 1, b = (e >> 1) & 1;
        for (int end = 0; end < 2; end++) {
            float p[3], bits[3];
            bits[axis] = (float)end, bits[(axis + 1) % 3] = (float)a, bits[(axis + 2) % 3] = (float)b;
            p[0] = bits[0] ? hi.x : lo.x, p[1] = bits[1] ? hi.y : lo.y, p[2] = bits[2] ? hi.z : lo.z;
            glVertex3fv(p);
        }
    }
    glEnd();
    glViewport(0, 0, fbw, fbh);
}

void draw_image(int fbw, int fbh)
{
    int ww, wh;
    glfwGetWindowSize(G.win, &ww, &wh);
    float fscale = ww > 0 ? (float)fbw / ww : 1.0f;
    view_state *v = G.v;
    float rw = (float)v->want.rd.width, rh = (float)v->want.rd.height;
    float k = std::fmin(ww / rw, wh / rh);
    if (!v->size_fixed) k = 1.0f / fscale;
    G.sw = rw * k, G.sh = rh * k, G.ox = 0.5f * (ww - G.sw), G.oy = 0.5f * (wh - G.sh);
    glViewport(0, 0, fbw, fbh);
    glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    if (G.tex_w == 0) return;
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, ww, wh, 0, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, G.tex);
    glColor3f(1, 1, 1);
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0), glVertex2f(G.ox, G.oy);
    glTexCoord2f(1, 0), glVertex2f(G.ox + G.sw, G.oy);
    glTexCoord2f(1, 1), glVertex2f(G.ox + G.sw, G.oy + G.sh);
    glTexCoord2f(0, 1), glVertex2f(G.ox, G.oy + G.sh);
    glEnd();
    glDisable(GL_TEXTURE_2D);
    if (v->show_box) draw_box(fbw, fbh, fscale);
}


} // namespace

extern "C" void view_gui_wake(void)
{
    if (window_up) glfwPostEmptyEvent();
}

namespace {

// The window, its GL 2.1 context, ImGui and the image's texture; false after a message.
bool open_window(view_run *r)
{
    gl_calls exempt;
    view_state *v = r->v;
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        std::fprintf(stderr, "%s: cannot open a window: %s\n", v->cmd, G.glfw_error);
        return false;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    char title[512];
    std::snprintf(title, sizeof title, "lanecast view - %s", v->input);
    G.win = glfwCreateWindow(v->want.rd.width, v->want.rd.height, title, nullptr, nullptr);
    if (!G.win) {
        std::fprintf(stderr, "%s: cannot open an OpenGL 2.1 window: %s\n", v->cmd, G.glfw_error);
        glfwTerminate();
        return false;
    }
    glfwMakeContextCurrent(G.win);
    glfwSwapInterval(r->script || r->screenshot ? 0 : 1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini in the user's folder
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(G.win, false);
    ImGui_ImplOpenGL2_Init();
    glfwSetMouseButtonCallback(G.win, on_button);
    glfwSetCursorPosCallback(G.win, on_cursor);
    glfwSetScrollCallback(G.win, on_scroll);
    glfwSetKeyCallback(G.win, on_key);
    glfwSetCharCallback(G.win, ImGui_ImplGlfw_CharCallback);
    glGenTextures(1, &G.tex);
    glBindTexture(GL_TEXTURE_2D, G.tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    window_up = 1;
    return true;
}

void draw_frame(view_run *r, int fbw, int fbh)
{
    gl_calls exempt;
    view_state *v = r->v;
    draw_image(fbw, fbh);
    ImGui_ImplOpenGL2_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (v->show_ui) view_panels(v, r->ui_dev);
    ImGui::Render();
    ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(G.win);
}

} // namespace

extern "C" int view_gui_run(view_run *r)
{
    view_state *v = r->v;
    G = gui();
    G.run = r, G.v = v;
    if (!open_window(r)) return 1;
    int rc = 0;
    view_script *script = r->script;
    while (!glfwWindowShouldClose(G.win)) {
        // a script that runs its next command polls; otherwise the UI sleeps until an
        // event or a pass wakes it (a spinning UI thread would take a core from the render)
        {
            gl_calls exempt;
            if (script && !view_script_waiting(script)) glfwPollEvents();
            else glfwWaitEventsTimeout(0.05);
        }
        for (int k = 0; script && k < 4; k++) { // a few commands per UI frame
            int s = view_script_step(script, v, r->ui_dev);
            if (s <= 0) {
                script = nullptr;
                if (s < 0) rc = 1, v->quit_asked = 1;
            }
        }
        view_tick(v);
        int fbw, fbh;
        glfwGetFramebufferSize(G.win, &fbw, &fbh);
        if (!v->size_fixed) view_set_size(v, fbw, fbh);
        {
            gl_calls exempt;
            upload();
        }
        if (view_failed(v) && (v->save_pending || r->screenshot)) {
            std::fprintf(stderr, "%s: no refined frame to save: the render failed\n", v->cmd);
            v->save_pending = 0;
            if (r->screenshot) {
                rc = 1;
                break;
            }
        }
        if (v->save_pending && view_refined(v)) {
            v->save_pending--;
            view_save(v, r->ui_dev, nullptr);
        }
        if (r->screenshot && view_refined(v)) {
            if (view_save(v, r->ui_dev, r->screenshot)) rc = 1;
            break;
        }
        if (v->quit_asked && !v->save_pending) break;
        draw_frame(r, fbw, fbh);
    }
    pthread_mutex_lock(&v->mu);
    v->quit = 1;
    pthread_cond_broadcast(&v->cv);
    pthread_mutex_unlock(&v->mu);
    return rc;
}

// After the other threads have stopped (they may wake the UI until then).
extern "C" void view_gui_close(void)
{
    if (!G.win) return;
    gl_calls exempt;
    window_up = 0;
    glDeleteTextures(1, &G.tex);
    ImGui_ImplOpenGL2_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(G.win);
    glfwTerminate();
    G.win = nullptr;
}
