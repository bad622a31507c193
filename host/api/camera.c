/* The one camera implementation (SPEC.md "Camera and rays"), with cglm for the
 * basis. cglm types stay in this file. */
#include <math.h>
#include <cglm/cglm.h>
#include "host/kinds/kind.h"

static int finite3(lc_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

lc_status lc_camera_frame(const lc_box3 *bounds, float azimuth, float elevation, lc_camera *cam)
{
    if (!bounds || !cam) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_camera_frame: bounds and cam must not be NULL");
    if (!isfinite(azimuth) || !(elevation > -90.0f && elevation < 90.0f))
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT,
                         "lc_camera_frame: azimuth %g must be finite and elevation %g in (-90, 90) degrees",
                         (double)azimuth, (double)elevation);
    vec3 lo = {bounds->lo.x, bounds->lo.y, bounds->lo.z}, hi = {bounds->hi.x, bounds->hi.y, bounds->hi.z};
    vec3 centre, diag;
    glm_vec3_center(lo, hi, centre);
    glm_vec3_sub(hi, lo, diag);
    float radius = 0.5f * glm_vec3_norm(diag);
    if (!(radius > 0.0f) || !isfinite(radius)) radius = 1.0f;
    float fovy = cam->fovy > 0.0f && cam->fovy < 179.0f ? cam->fovy : 40.0f;
    /* perspective: the bounding sphere fills the vertical field of view; orthographic: any distance outside it */
    float dist = cam->projection == LC_ORTHOGRAPHIC ? 2.0f * radius : radius / sinf(glm_rad(fovy) * 0.5f) * 1.05f;
    float az = glm_rad(azimuth), el = glm_rad(elevation);
    cam->at = (lc_vec3){centre[0], centre[1], centre[2]};
    cam->eye = (lc_vec3){centre[0] + dist * cosf(el) * sinf(az), centre[1] + dist * sinf(el),
                         centre[2] + dist * cosf(el) * cosf(az)};
    cam->up = (lc_vec3){0.0f, 1.0f, 0.0f};
    return LC_OK;
}

lc_status lci_camera_build(lc_device *dev, const lc_camera *cam, int width, int height, const lc_box3 *bounds,
                           lc_kcamera *out)
{
    if (cam->projection != LC_PERSPECTIVE && cam->projection != LC_ORTHOGRAPHIC)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "camera: projection %d is not perspective or orthographic",
                         (int)cam->projection);
    if (!finite3(cam->eye) || !finite3(cam->at) || !finite3(cam->up))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "camera: eye, at and up must be finite");
    float fovy = cam->fovy == 0.0f ? 40.0f : cam->fovy;
    if (!(fovy > 0.0f && fovy < 179.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "camera: fovy = %g degrees, expected (0, 179)", (double)fovy);
    if (cam->projection == LC_ORTHOGRAPHIC && !(cam->height >= 0.0f && isfinite(cam->height)))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "camera: orthographic height = %g, expected > 0",
                         (double)cam->height);
    vec3 eye = {cam->eye.x, cam->eye.y, cam->eye.z}, at = {cam->at.x, cam->at.y, cam->at.z};
    vec3 up = {cam->up.x, cam->up.y, cam->up.z};
    if (glm_vec3_norm(up) == 0.0f) glm_vec3_copy((vec3){0.0f, 1.0f, 0.0f}, up);
    float upmax = fmaxf(fabsf(up[0]), fmaxf(fabsf(up[1]), fabsf(up[2])));
    if (upmax > 0.0f) glm_vec3_scale(up, 1.0f / upmax, up); /* a direction: its length must not overflow */
    vec3 lo = {bounds->lo.x, bounds->lo.y, bounds->lo.z}, hi = {bounds->hi.x, bounds->hi.y, bounds->hi.z};
    vec3 centre, diag;
    glm_vec3_center(lo, hi, centre);
    glm_vec3_sub(hi, lo, diag);
    float radius = 0.5f * glm_vec3_norm(diag);
    if (!(radius > 0.0f) || !isfinite(radius)) radius = 1.0f;
    float ortho_h = cam->height;
    if (glm_vec3_distance(eye, at) == 0.0f) {
        /* default view: an oblique three-quarter view of the centre, the bounding sphere filling the frame */
        lc_camera c = *cam;
        lc_camera_frame(bounds, LC_CAMERA_AZIMUTH, LC_CAMERA_ELEVATION, &c);
        glm_vec3_copy((vec3){c.eye.x, c.eye.y, c.eye.z}, eye);
        glm_vec3_copy((vec3){c.at.x, c.at.y, c.at.z}, at);
        glm_vec3_copy((vec3){c.up.x, c.up.y, c.up.z}, up);
    }
    if (cam->projection == LC_ORTHOGRAPHIC && ortho_h == 0.0f) ortho_h = 2.1f * radius;
    vec3 fwd, right, upv;
    glm_vec3_sub(at, eye, fwd);
    /* scaled before normalising: |at - eye|^2 overflows float beyond ~1.8e19,
       which made a far eye look like "up is parallel" */
    float big = fmaxf(fabsf(fwd[0]), fmaxf(fabsf(fwd[1]), fabsf(fwd[2])));
    if (!isfinite(big))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "camera: eye (%g, %g, %g) and at (%g, %g, %g) are too far apart for float arithmetic", (double)eye[0],
                         (double)eye[1], (double)eye[2], (double)at[0], (double)at[1], (double)at[2]);
    glm_vec3_scale(fwd, 1.0f / big, fwd);
    glm_vec3_normalize(fwd);
    glm_vec3_cross(fwd, up, right);
    if (glm_vec3_norm(right) < 1e-6f * glm_vec3_norm(up))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "camera: up (%g, %g, %g) is parallel to the view direction",
                         (double)up[0], (double)up[1], (double)up[2]);
    glm_vec3_normalize(right);
    glm_vec3_cross(right, fwd, upv);
    float aspect = (float)width / (float)height;
    float sx, sy;
    if (cam->projection == LC_ORTHOGRAPHIC) {
        sy = 0.5f * ortho_h;
    } else {
        sy = tanf(glm_rad(fovy) * 0.5f);
    }
    sx = sy * aspect;
    for (int k = 0; k < 3; k++) {
        out->eye[k] = eye[k];
        out->forward[k] = fwd[k];
        out->right[k] = right[k] * sx;
        out->up[k] = upv[k] * sy;
    }
    out->eye[3] = out->forward[3] = out->right[3] = out->up[3] = 0.0f;
    out->width = width;
    out->height = height;
    out->ortho = cam->projection == LC_ORTHOGRAPHIC;
    out->pad = 0;
    return LC_OK;
}

/* The camera of a pass at pixel scale s (lc_render_desc.pixel_scale): an
 * image of ceil(w / s) x ceil(h / s) pixels whose pixel (i, j) takes the ray
 * of pixel (s i, s j) of the w x h image. Pixel centres map affinely,
 * u_full = a u + b (kernels/dvr.h), so the basis is scaled by a and the
 * offset b moves the direction (perspective) or the origin (orthographic). */
void lci_camera_subsample(lc_kcamera *c, int s)
{
    int w = c->width, h = c->height;
    int pw = (w + s - 1) / s, ph = (h + s - 1) / s;
    double ax = (double)s * pw / w, bx = ax - 1.0 + (1.0 - s) / w;
    double ay = (double)s * ph / h, by = 1.0 + (s - 1.0) / h - ay;
    float *base = c->ortho ? c->eye : c->forward;
    for (int k = 0; k < 3; k++) {
        base[k] = (float)(base[k] + bx * c->right[k] + by * c->up[k]);
        c->right[k] = (float)(ax * c->right[k]);
        c->up[k] = (float)(ay * c->up[k]);
    }
    c->width = pw;
    c->height = ph;
}
