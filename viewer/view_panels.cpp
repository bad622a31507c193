// The overlay and panels of lanecast view (Dear ImGui). Every value goes
// through view_setf / view_set / the TF edits, as --script's commands do; the
// UI thread is the only writer of view_state.want, so it reads it unlocked.
#include <imgui.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include "view_gui.h"

namespace {

int tf_drag = -1, tf_field = 0;
float tf_ymax[LC_MAX_FIELDS];
char tf_path[512] = "lanecast-view-tf.json";

void slider(view_state *v, const char *label, const char *name, bool log = false)
{
    float lo, hi;
    int integer;
    if (view_param_bounds(v, name, &lo, &hi, &integer)) return;
    if (integer) {
        int x = (int)view_getf(v, name);
        if (ImGui::SliderInt(label, &x, (int)lo, (int)hi)) view_setf(v, name, (float)x);
    } else {
        float x = view_getf(v, name);
        if (ImGui::SliderFloat(label, &x, lo, hi, "%.4g", log && lo > 0 ? ImGuiSliderFlags_Logarithmic : 0))
            view_setf(v, name, x);
    }
}

void combo(view_state *v, const char *label, const char *name, const char *const *names, int n, int current)
{
    if (current < 0 || current >= n) current = 0;
    if (!ImGui::BeginCombo(label, names[current])) return;
    for (int i = 0; i < n; i++)
        if (ImGui::Selectable(names[i], i == current)) view_set(v, name, names[i]);
    ImGui::EndCombo();
}

void overlay(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    view_shown s = v->shown;
    s.rgba = nullptr;
    int refined = v->refined_gen == v->want.gen, nav = v->want.nav;
    long long frame = v->frame, frames = v->frames, loading = v->frame_loading;
    bool playing = v->playing;
    char ferr[512];
    std::snprintf(ferr, sizeof ferr, "%s", v->frame_error);
    pthread_mutex_unlock(&v->mu);
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.55f);
    ImGui::Begin("overlay", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoFocusOnAppearing |
                     ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs);
    ImGui::Text("%s  %dx%d  %s", v->input, v->want.rd.width, v->want.rd.height,
                nav ? "navigating" : refined ? "refined" : "refining");
    double fs = s.pass_seconds > 0 ? s.pass_seconds : 0;
    ImGui::Text("pass %d/%d (scale %d)  frame %.1f ms  %.1f fps", s.pass, s.npasses, s.scale, 1e3 * fs,
                fs > 0 ? 1.0 / fs : 0.0);
    double js = s.job_seconds > 0 ? s.job_seconds : 1e-9;
    ImGui::Text("%.1f M samples/s  %.1f M %s/s", s.stats.samples / js / 1e6, s.stats.kernel_evals / js / 1e6,
                v->vinfo.kind == LC_KIND_GRID ? "voxels" : "Gaussians");
    ImGui::Text("target %s (%d lanes), %d threads  nav scale %d%s  UI %.0f fps", lc_target_name(s.target),
                lc_target_lanes(s.target), s.threads, v->want.nav_scale, v->adaptive ? " (adaptive)" : "",
                ImGui::GetIO().Framerate);
    if (frames > 1)
        ImGui::Text("frame %lld of %lld%s%s", frame, frames, loading >= 0 ? "  (loading the next)" : "",
                    playing ? "  playing" : "");
    if (s.error[0]) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", s.error);
    if (ferr[0]) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ferr);
    if (v->status[0]) ImGui::TextWrapped("%s", v->status);
    ImGui::End();
}

// The opacity curve over the log-scaled histogram: click to add a point, drag
// to move it, right-click to delete it.
void tf_curve(view_state *v)
{
    const view_tf &t = v->want.tf;
    int f = tf_field < t.nfields ? tf_field : 0;
    const float *p = t.opacity[f];
    int n = t.nopacity[f];
    if (!(tf_ymax[f] > 0)) {
        for (int k = 0; k < n; k++) tf_ymax[f] = std::fmax(tf_ymax[f], 1.5f * p[2 * k + 1]);
        if (!(tf_ymax[f] > 0)) tf_ymax[f] = 1.0f;
    }
    ImVec2 p0 = ImGui::GetCursorScreenPos(), sz(ImGui::GetContentRegionAvail().x, 120.0f);
    ImGui::InvisibleButton("tf", sz, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    ImDrawList *dl = ImGui::GetWindowDrawList();
    ImVec2 p1(p0.x + sz.x, p0.y + sz.y);
    dl->AddRectFilled(p0, p1, IM_COL32(30, 30, 35, 255));
    float lo = view_getf(v, "range_lo"), hi = view_getf(v, "range_hi");
    pthread_mutex_lock(&v->mu);
    view_hist h = v->hist;
    pthread_mutex_unlock(&v->mu);
    if (h.ready && hi > lo && f < h.nfields) {
        float bw = (h.range[1] - h.range[0]) / VIEW_HIST_BINS;
        for (int b = 0; b < VIEW_HIST_BINS; b++) {
            float a = (h.range[0] + b * bw - lo) / (hi - lo), c = (h.range[0] + (b + 1) * bw - lo) / (hi - lo);
            if (c < 0 || a > 1) continue;
            a = std::fmax(a, 0.0f), c = std::fmin(c, 1.0f);
            dl->AddRectFilled(ImVec2(p0.x + a * sz.x, p1.y - h.log_counts[f][b] * sz.y), ImVec2(p0.x + c * sz.x, p1.y),
                              IM_COL32(90, 90, 110, 255));
        }
    } else {
        dl->AddText(ImVec2(p0.x + 4, p0.y + 4), IM_COL32(150, 150, 150, 255), "histogram: computing");
    }
    auto pos = [&](int k) {
        return ImVec2(p0.x + p[2 * k] * sz.x, p1.y - std::fmin(p[2 * k + 1] / tf_ymax[f], 1.0f) * sz.y);
    };
    for (int k = 0; k + 1 < n; k++) dl->AddLine(pos(k), pos(k + 1), IM_COL32(255, 220, 120, 255), 2.0f);
    ImVec2 m = ImGui::GetIO().MousePos;
    int hover = -1;
    for (int k = 0; k < n; k++) {
        ImVec2 q = pos(k);
        if (std::fabs(q.x - m.x) < 6 && std::fabs(q.y - m.y) < 6) hover = k;
        dl->AddCircleFilled(q, 4.0f, k == hover ? IM_COL32(255, 255, 255, 255) : IM_COL32(255, 200, 80, 255));
    }
    float mx = (m.x - p0.x) / sz.x, my = (p1.y - m.y) / sz.y * tf_ymax[f];
    mx = std::fmin(std::fmax(mx, 0.0f), 1.0f), my = std::fmin(std::fmax(my, 0.0f), tf_ymax[f]);
    if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (hover >= 0) tf_drag = hover;
        else {
            view_tf_point(v, f, n, mx, my);
            for (int k = 0; k < t.nopacity[f]; k++)
                if (t.opacity[f][2 * k] == mx && t.opacity[f][2 * k + 1] == my) tf_drag = k;
        }
    } else if (tf_drag >= 0 && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
        if (tf_drag < t.nopacity[f] && (p[2 * tf_drag] != mx || p[2 * tf_drag + 1] != my))
            view_tf_point(v, f, tf_drag, mx, my);
    } else {
        tf_drag = -1;
    }
    if (ImGui::IsItemHovered() && ImGui::IsMouseClicked(ImGuiMouseButton_Right) && hover >= 0)
        view_tf_delete_point(v, f, hover);
    // the colour map under the curve
    ImVec2 c0 = ImGui::GetCursorScreenPos();
    const float *col = t.color[f];
    for (int k = 0; k + 1 < t.ncolor[f]; k++) {
        const float *a = col + 4 * k, *b = col + 4 * k + 4;
        auto rgb = [](const float *c) {
            return IM_COL32((int)(255 * std::fmin(std::fmax(c[1], 0.f), 1.f)), (int)(255 * std::fmin(std::fmax(c[2], 0.f), 1.f)),
                            (int)(255 * std::fmin(std::fmax(c[3], 0.f), 1.f)), 255);
        };
        dl->AddRectFilledMultiColor(ImVec2(c0.x + a[0] * sz.x, c0.y), ImVec2(c0.x + b[0] * sz.x, c0.y + 10), rgb(a), rgb(b),
                                    rgb(b), rgb(a));
    }
    ImGui::Dummy(ImVec2(sz.x, 12));
    ImGui::Text("tau up to %.4g per unit; value %.4g .. %.4g", (double)tf_ymax[f], (double)lo, (double)hi);
}

void tf_panel(view_state *v)
{
    if (!ImGui::CollapsingHeader("Transfer function", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const view_tf &t = v->want.tf;
    if (t.nfields > 1) ImGui::SliderInt("field##tf", &tf_field, 0, t.nfields - 1);
    tf_curve(v);
    const char *cur = t.colormap[0] ? t.colormap : "(the input's)";
    if (ImGui::BeginCombo("colour map", cur)) {
        for (int i = 0; lc_tf_preset_name(i); i++)
            if (ImGui::Selectable(lc_tf_preset_name(i), !std::strcmp(cur, lc_tf_preset_name(i))))
                view_tf_colormap(v, lc_tf_preset_name(i));
        ImGui::EndCombo();
    }
    slider(v, "range lo", "range_lo");
    slider(v, "range hi", "range_hi");
    if (ImGui::Button("reset to data")) {
        view_setf(v, "range_lo", v->vinfo.range[0]);
        view_setf(v, "range_hi", v->vinfo.range[1]);
    }
    slider(v, "opacity scale", "opacity_scale");
    ImGui::InputText("##tfpath", tf_path, sizeof tf_path);
    ImGui::SameLine();
    if (ImGui::Button("save TF")) view_tf_save(v, tf_path);
}

void render_panel(view_state *v)
{
    if (!ImGui::CollapsingHeader("Render", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const lc_render_desc &rd = v->want.rd;
    combo(v, "mode", "mode", view_modes, 4, rd.mode);
    if (rd.mode == LC_MODE_ISO) slider(v, "iso value", "iso");
    if (rd.mode == LC_MODE_SLICE) {
        static const char *const axes[3] = {"x", "y", "z"};
        int a = v->plane_axis;
        if (ImGui::Combo("plane normal", &a, axes, 3)) view_setf(v, "plane_axis", (float)a);
        slider(v, "plane position", "plane_pos");
    }
    if ((rd.mode == LC_MODE_ISO || rd.mode == LC_MODE_SLICE) && v->vinfo.nfields > 1) slider(v, "field", "field");
    combo(v, "shading", "shading", view_shadings, 3, rd.shading);
    if (rd.shading != LC_SHADE_NONE) {
        slider(v, "ambient ka", "ka");
        slider(v, "diffuse kd", "kd");
        if (rd.shading == LC_SHADE_PHONG) {
            slider(v, "specular ks", "ks");
            slider(v, "Phong exponent", "phong_exp");
        }
    }
    slider(v, "alpha stop", "alpha_stop");
    slider(v, "dt (0 = default)", "dt");
    // the methods of the data's kind (lc_method); "default" is the fast one of each
    static const char *const pm[] = {"default", "coherent", "direct"}, *const gm[] = {"default", "bvh", "brute"},
                             *const rm[] = {"default", "coherent", "bvh", "brute"};
    const char *const *ms = v->vinfo.kind == LC_KIND_PARTICLES ? pm : v->vinfo.kind == LC_KIND_GRID ? gm : rm;
    int nm = v->vinfo.kind == LC_KIND_RBF ? 4 : 3, cur = 0;
    for (int i = 0; i < nm; i++)
        if (!std::strcmp(ms[i], view_methods[rd.method])) cur = i;
    combo(v, "method", "method", ms, nm, cur);
    if (v->vinfo.kind == LC_KIND_PARTICLES) {
        slider(v, "sigma", "sigma");
        slider(v, "kappa", "kappa", true);
    }
    bool box = v->show_box;
    if (ImGui::Checkbox("bounding box", &box)) view_setf(v, "box", box ? 1.0f : 0.0f);
}

void exec_panel(view_state *v)
{
    if (!ImGui::CollapsingHeader("Execution and navigation")) return;
    static const char *names[LC_TARGET_COUNT];
    int n = 0, cur = 0;
    for (int t = 0; t < LC_TARGET_COUNT; t++)
        if (lc_target_compiled((lc_target)t) && lc_target_supported((lc_target)t)) {
            if (t == v->want.target) cur = n;
            names[n++] = lc_target_name((lc_target)t);
        }
    combo(v, "SIMD target", "target", names, n, cur);
    slider(v, "threads (0 = all)", "threads");
    bool ad = v->adaptive;
    if (ImGui::Checkbox("adaptive navigation", &ad)) view_setf(v, "adaptive", ad ? 1.0f : 0.0f);
    slider(v, "navigation scale", "nav_scale");
    slider(v, "navigation step", "nav_step");
    slider(v, "target frame ms", "target_ms");
    slider(v, "refine delay s", "refine_delay");
}

void frames_panel(view_state *v)
{
    if (v->frames <= 1 || !ImGui::CollapsingHeader("Frames", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (ImGui::Button("<")) view_frames_command(v, "step", -1);
    ImGui::SameLine();
    pthread_mutex_lock(&v->mu);
    bool playing = v->playing;
    pthread_mutex_unlock(&v->mu);
    if (ImGui::Button(playing ? "pause" : "play")) view_frames_command(v, playing ? "pause" : "play", 0);
    ImGui::SameLine();
    if (ImGui::Button(">")) view_frames_command(v, "step", 1);
    pthread_mutex_lock(&v->mu);
    int f = (int)v->frame;
    pthread_mutex_unlock(&v->mu);
    if (ImGui::SliderInt("frame", &f, 0, (int)v->frames - 1)) view_frames_command(v, "frame", f);
}

} // namespace

void view_panels(view_state *v, lc_device *)
{
    overlay(v);
    ImGuiIO &io = ImGui::GetIO();
    // collapsed at first, at the top right: the image stays free for the mouse
    float w = io.DisplaySize.x - 16 < 340 ? io.DisplaySize.x - 16 : 340;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - 8, 8), ImGuiCond_FirstUseEver, ImVec2(1, 0));
    ImGui::SetNextWindowSize(ImVec2(w, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
    if (v->panels_asked) ImGui::SetNextWindowCollapsed(!v->panels_open, ImGuiCond_Always);
    v->panels_asked = 0;
    ImGui::Begin("lanecast view (h hides)");
    tf_panel(v);
    render_panel(v);
    exec_panel(v);
    frames_panel(v);
    ImGui::End();
}
