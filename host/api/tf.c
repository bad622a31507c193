/* Transfer functions: creation from points, SPEC.md's JSON format (json-c;
 * compiled out with -Djson=disabled, when parsing says what is missing),
 * presets, evaluation and the kernel lookup table. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/api/tf.h"
#include "host/formats/checked.h"
#if LC_HAVE_JSON
#include <json-c/json.h>
#endif

static void free_points(lc_tf *tf)
{
    for (int f = 0; f < tf->nfields; f++) {
        free(tf->field[f].color);
        free(tf->field[f].opacity);
    }
}

void lc_tf_destroy(lc_tf *tf)
{
    if (!tf) return;
    free_points(tf);
    free(tf);
}

int lc_tf_field_count(const lc_tf *tf) { return tf ? tf->nfields : 0; }

lc_status lc_tf_get_field(const lc_tf *tf, int field, lc_tf_field *out)
{
    if (!tf || !out || field < 0 || field >= tf->nfields)
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_tf_get_field: no field %d (the TF has %d) or a NULL argument",
                         field, tf ? tf->nfields : 0);
    const lci_tf_points *p = &tf->field[field];
    memset(out, 0, sizeof *out);
    out->color = p->color;
    out->ncolor = p->ncolor;
    out->opacity = p->opacity;
    out->nopacity = p->nopacity;
    out->has_range = p->has_range;
    out->range[0] = p->range[0];
    out->range[1] = p->range[1];
    return LC_OK;
}

int lc_tf_default_opacity(const lc_tf *tf, int field)
{
    return tf && field >= 0 && field < tf->nfields ? tf->field[field].default_opacity : 0;
}

static lc_status check_points(lc_device *dev, const char *where, int f, const char *what, const float *p, int n,
                              int stride)
{
    if (!p || n < 1) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: %s has no points", where, f, what);
    if (n > 65536) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: %s has %d points (at most 65536)", where, f, what, n);
    for (int i = 0; i < n; i++) {
        const float *q = p + (size_t)i * (size_t)stride;
        for (int c = 0; c < stride; c++)
            if (!isfinite(q[c]))
                return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: %s point %d is not finite", where, f, what, i);
        if (q[0] < 0.0f || q[0] > 1.0f)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: field %d: %s point %d has v = %g outside [0, 1] (v is the normalised value)", where, f,
                             what, i, (double)q[0]);
        if (i > 0 && q[0] < q[-stride])
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: %s point %d: v = %g decreases (previous %g)",
                             where, f, what, i, (double)q[0], (double)q[-stride]);
        if (stride == 2 && q[1] < 0.0f)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: opacity point %d has tau = %g < 0", where, f,
                             i, (double)q[1]);
    }
    return LC_OK;
}

static lc_status create(lc_device *dev, const char *where, const lc_tf_field *fields, int nfields, lc_tf **out)
{
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: out is NULL", where);
    *out = NULL;
    if (!fields) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields is NULL", where);
    if (nfields < 1 || nfields > LC_MAX_FIELDS)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %d fields, expected 1 to %d", where, nfields, LC_MAX_FIELDS);
    for (int f = 0; f < nfields; f++) {
        lc_status s = check_points(dev, where, f, "color", fields[f].color, fields[f].ncolor, 4);
        if (s == LC_OK) s = check_points(dev, where, f, "opacity", fields[f].opacity, fields[f].nopacity, 2);
        if (s != LC_OK) return s;
        if (fields[f].has_range && !(isfinite(fields[f].range[0]) && isfinite(fields[f].range[1]) &&
                                     fields[f].range[1] > fields[f].range[0]))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d: range [%g, %g] is empty or not finite",
                             where, f, (double)fields[f].range[0], (double)fields[f].range[1]);
    }
    lc_tf *tf = calloc(1, sizeof *tf);
    if (!tf) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", where);
    tf->nfields = nfields;
    for (int f = 0; f < nfields; f++) {
        lci_tf_points *p = &tf->field[f];
        p->color = malloc(sizeof(float) * 4 * (size_t)fields[f].ncolor);
        p->opacity = malloc(sizeof(float) * 2 * (size_t)fields[f].nopacity);
        if (!p->color || !p->opacity) {
            lc_tf_destroy(tf);
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", where);
        }
        memcpy(p->color, fields[f].color, sizeof(float) * 4 * (size_t)fields[f].ncolor);
        memcpy(p->opacity, fields[f].opacity, sizeof(float) * 2 * (size_t)fields[f].nopacity);
        p->ncolor = fields[f].ncolor;
        p->nopacity = fields[f].nopacity;
        p->has_range = fields[f].has_range;
        p->range[0] = fields[f].range[0];
        p->range[1] = fields[f].range[1];
    }
    *out = tf;
    return LC_OK;
}

lc_status lc_tf_create(lc_device *device, const lc_tf_field *fields, int nfields, lc_tf **out)
{
    return create(device, "lc_tf_create", fields, nfields, out);
}

/* ---- evaluation */

static void eval_points(const float *p, int n, int stride, int nc, double v, double *out)
{
    if (v <= p[0]) {
        for (int c = 0; c < nc; c++) out[c] = p[1 + c];
        return;
    }
    const float *last = p + (size_t)(n - 1) * (size_t)stride;
    if (v >= last[0]) {
        for (int c = 0; c < nc; c++) out[c] = last[1 + c];
        return;
    }
    for (int i = 1; i < n; i++) {
        const float *a = p + (size_t)(i - 1) * (size_t)stride, *b = a + stride;
        if (v <= b[0]) {
            double w = b[0] > a[0] ? (v - a[0]) / (b[0] - a[0]) : 1.0;
            for (int c = 0; c < nc; c++) out[c] = a[1 + c] + w * (b[1 + c] - a[1 + c]);
            return;
        }
    }
    for (int c = 0; c < nc; c++) out[c] = last[1 + c];
}

void lci_tf_eval(const lc_tf *tf, int field, double v, double rgb[3], double *tau)
{
    const lci_tf_points *p = &tf->field[field];
    eval_points(p->color, p->ncolor, 4, 3, v, rgb);
    eval_points(p->opacity, p->nopacity, 2, 1, v, tau);
}

void lci_tf_fill(const lc_tf *tf, int field, float lo, float hi, float *table, lc_ktf *out)
{
    for (int j = 0; j < LC_TF_TABLE_SIZE; j++) {
        double rgb[3], tau;
        lci_tf_eval(tf, field, (double)j / (LC_TF_TABLE_SIZE - 1), rgb, &tau);
        table[4 * j + 0] = (float)rgb[0];
        table[4 * j + 1] = (float)rgb[1];
        table[4 * j + 2] = (float)rgb[2];
        table[4 * j + 3] = (float)tau;
    }
    out->rgbt = table;
    out->lo = lo;
    out->inv_range = 1.0f / (hi - lo);
    out->cls = NULL;
    out->cls_vzero = -1.0f;
    out->grad_eps = 0.0f;
}

/* The largest field value a dvr sample may have and still be fully
 * transparent in this TF (tau = 0 at every value at or below it; the table
 * is clamped below v = 0), or -inf. dvr_classify_v interpolates entries i and
 * i + 1 at x = v (N - 1): with entries 0..j at tau = 0, any x <= j gives 0;
 * the bound keeps 1% of an entry from j against the normalisation's
 * round-off. */
float lci_tf_clear_below(const lc_ktf *tf)
{
    int j = -1;
    while (j + 1 < LC_TF_TABLE_SIZE && tf->rgbt[4 * (j + 1) + 3] == 0.0f) j++;
    if (j < 0 || !(tf->inv_range > 0.0f) || !isfinite(tf->inv_range)) return -INFINITY;
    if (j == LC_TF_TABLE_SIZE - 1) return INFINITY;
    if (j == 0) return tf->lo; /* v <= 0 exactly: x = 0, weight 0 */
    return tf->lo + ((float)j - 0.01f) / ((float)(LC_TF_TABLE_SIZE - 1) * tf->inv_range);
}

/* One step's classification of a kernel TF for the frame's dt (kframe.h
 * lc_ktf cls): opacity a = 1 - exp(-tau dt) and the colour premultiplied by
 * it at each entry, plus a copy of the last entry, into cls ((LC_TF_TABLE_SIZE
 * + 1) * 4 floats), and the largest normalised value at and below which tau
 * is 0 (the table's entries 0..e0-1 are 0, and interpolating between entries
 * e0-1 and e0 gives 0 only at e0-1). */
void lci_tf_step_table(float dt, float *cls, lc_ktf *tf)
{
    const float *t = tf->rgbt;
    for (int e = 0; e <= LC_TF_TABLE_SIZE; e++) {
        const float *q = t + 4 * (e < LC_TF_TABLE_SIZE ? e : LC_TF_TABLE_SIZE - 1);
        float a = 1.0f - expf(-q[3] * dt);
        cls[4 * e] = a * q[0], cls[4 * e + 1] = a * q[1], cls[4 * e + 2] = a * q[2], cls[4 * e + 3] = a;
    }
    int e0 = 0;
    while (e0 < LC_TF_TABLE_SIZE && t[4 * e0 + 3] == 0.0f) e0++;
    tf->cls = cls;
    tf->cls_vzero = e0 == 0 ? -1.0f : e0 == LC_TF_TABLE_SIZE ? 2.0f : (float)(e0 - 1) / (float)(LC_TF_TABLE_SIZE - 1);
}

/* ---- JSON */

#if LC_HAVE_JSON

typedef struct parse_ctx {
    lc_device *dev;
    const char *name;
} parse_ctx;

static lc_status read_pairs(parse_ctx *c, int f, json_object *arr, const char *key, int width, float **out, int *n)
{
    if (!arr || !json_object_is_type(arr, json_type_array))
        return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: \"%s\" must be an array of [v, ...] points", c->name,
                         f, key);
    size_t len = json_object_array_length(arr);
    if (len == 0) return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: \"%s\" is empty", c->name, f, key);
    float *p = calloc(len * (size_t)width, sizeof(float));
    if (!p) return lci_error(c->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->name);
    for (size_t i = 0; i < len; i++) {
        json_object *pt = json_object_array_get_idx(arr, i);
        if (!json_object_is_type(pt, json_type_array) || (int)json_object_array_length(pt) != width) {
            free(p);
            return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: \"%s\"[%zu] must be an array of %d numbers (%s)",
                             c->name, f, key, i, width, width == 4 ? "[v, r, g, b]" : "[v, tau]");
        }
        for (int k = 0; k < width; k++) {
            json_object *num = json_object_array_get_idx(pt, (size_t)k);
            if (!json_object_is_type(num, json_type_double) && !json_object_is_type(num, json_type_int)) {
                free(p);
                return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: \"%s\"[%zu][%d] is not a number", c->name, f,
                                 key, i, k);
            }
            p[i * (size_t)width + (size_t)k] = (float)json_object_get_double(num);
        }
    }
    *out = p;
    *n = (int)len;
    return LC_OK;
}

static lc_status read_field(parse_ctx *c, int f, json_object *o, lc_tf_field *out, float **keep_c, float **keep_o)
{
    if (!json_object_is_type(o, json_type_object))
        return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d is not a JSON object", c->name, f);
    json_object *col = NULL, *op = NULL, *range = NULL;
    json_object_object_get_ex(o, "color", &col);
    json_object_object_get_ex(o, "opacity", &op);
    if (!col) return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: missing \"color\"", c->name, f);
    if (!op) return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: missing \"opacity\"", c->name, f);
    memset(out, 0, sizeof *out);
    lc_status s = read_pairs(c, f, col, "color", 4, keep_c, &out->ncolor);
    if (s != LC_OK) return s;
    out->color = *keep_c;
    s = read_pairs(c, f, op, "opacity", 2, keep_o, &out->nopacity);
    if (s != LC_OK) return s;
    out->opacity = *keep_o;
    if (json_object_object_get_ex(o, "range", &range)) {
        if (!json_object_is_type(range, json_type_array) || json_object_array_length(range) != 2)
            return lci_error(c->dev, LC_ERROR_FORMAT, "%s: field %d: \"range\" must be [lo, hi]", c->name, f);
        out->has_range = 1;
        out->range[0] = (float)json_object_get_double(json_object_array_get_idx(range, 0));
        out->range[1] = (float)json_object_get_double(json_object_array_get_idx(range, 1));
    }
    return LC_OK;
}


/* ParaView colour-map presets (File > Save of the Color Map Editor's preset
 * dialog): an array of objects with "Name", "RGBPoints" [x, r, g, b, ...] and
 * optionally "Points" [x, alpha, midpoint, sharpness, ...]. The first preset
 * with RGBPoints is read. As ParaView does when it applies a preset, x is
 * rescaled: the RGBPoints' [x_min, x_max] becomes v = [0, 1], so the TF maps
 * the data's range (or --range / lc_render_desc.range), not the preset's.
 * Opacity alpha (per unit distance, ParaView's default "Scalar Opacity Unit
 * Distance" of 1) becomes the extinction tau = -ln(1 - alpha) per world unit,
 * alpha clamped to 0.999; without "Points", tau ramps from 0 to 1 and the
 * field says default_opacity = 1 so that callers may substitute their own.
 * Midpoint and sharpness are ignored (linear segments), and colours are
 * interpolated in RGB whatever "ColorSpace" says. */
static lc_status read_flat(parse_ctx *c, json_object *arr, const char *key, int group, float **out, int *n)
{
    size_t len = arr && json_object_is_type(arr, json_type_array) ? json_object_array_length(arr) : 0;
    if (len < (size_t)group || len % (size_t)group)
        return lci_error(c->dev, LC_ERROR_FORMAT, "%s: ParaView preset: \"%s\" must be a flat array of groups of %d numbers",
                         c->name, key, group);
    float *p = malloc(sizeof(float) * len);
    if (!p) return lci_error(c->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->name);
    for (size_t i = 0; i < len; i++) {
        json_object *num = json_object_array_get_idx(arr, i);
        if (!json_object_is_type(num, json_type_double) && !json_object_is_type(num, json_type_int)) {
            free(p);
            return lci_error(c->dev, LC_ERROR_FORMAT, "%s: ParaView preset: \"%s\"[%zu] is not a number", c->name, key, i);
        }
        p[i] = (float)json_object_get_double(num);
    }
    *out = p;
    *n = (int)(len / (size_t)group);
    return LC_OK;
}

static lc_status read_paraview(parse_ctx *c, json_object *root, lc_tf **out)
{
    json_object *preset = NULL, *rgb = NULL, *pts = NULL;
    size_t len = json_object_is_type(root, json_type_array) ? json_object_array_length(root) : 1;
    for (size_t i = 0; i < len && !preset; i++) {
        json_object *o = json_object_is_type(root, json_type_array) ? json_object_array_get_idx(root, i) : root;
        if (json_object_is_type(o, json_type_object) && json_object_object_get_ex(o, "RGBPoints", &rgb)) preset = o;
    }
    if (!preset)
        return lci_error(c->dev, LC_ERROR_FORMAT,
                         "%s: a JSON array but no ParaView preset in it (an object with \"RGBPoints\")", c->name);
    float *cp = NULL, *op = NULL, *col = NULL, *opa = NULL;
    int nc = 0, no = 0;
    lc_status s = read_flat(c, rgb, "RGBPoints", 4, &cp, &nc);
    if (s == LC_OK && json_object_object_get_ex(preset, "Points", &pts)) s = read_flat(c, pts, "Points", 4, &op, &no);
    float x0 = s == LC_OK ? cp[0] : 0.0f, x1 = s == LC_OK ? cp[4 * (nc - 1)] : 0.0f;
    if (s == LC_OK && !(x1 > x0))
        s = lci_error(c->dev, LC_ERROR_FORMAT, "%s: ParaView preset: \"RGBPoints\" x values %g..%g are not increasing",
                      c->name, (double)x0, (double)x1);
    if (s == LC_OK) {
        col = malloc(sizeof(float) * 4 * (size_t)nc);
        opa = malloc(sizeof(float) * 2 * (size_t)(no > 0 ? no : 2));
        if (!col || !opa) s = lci_error(c->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->name);
    }
    for (int i = 0; s == LC_OK && i < nc; i++) {
        float v = (cp[4 * i] - x0) / (x1 - x0);
        col[4 * i] = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
        for (int k = 1; k < 4; k++) col[4 * i + k] = cp[4 * i + k];
    }
    lc_tf_field f;
    memset(&f, 0, sizeof f);
    int stand_in = 0;
    for (int i = 0; s == LC_OK && i < no; i++) {
        float v = (op[4 * i] - x0) / (x1 - x0), a = op[4 * i + 1];
        opa[2 * i] = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
        a = a < 0.0f ? 0.0f : a > 0.999f ? 0.999f : a;
        opa[2 * i + 1] = (float)-log1p(-(double)a);
    }
    if (s == LC_OK && no == 0) {
        opa[0] = 0.0f, opa[1] = 0.0f, opa[2] = 1.0f, opa[3] = 1.0f;
        no = 2;
        stand_in = 1;
    }
    if (s == LC_OK) {
        f.color = col, f.ncolor = nc, f.opacity = opa, f.nopacity = no;
        s = create(c->dev, c->name, &f, 1, out);
        if (s == LC_OK) (*out)->field[0].default_opacity = stand_in;
    }
    free(cp), free(op), free(col), free(opa);
    return s;
}

/* What is still open at the end of a truncated JSON text: the innermost of
 * a string, an array or an object (for the message). */
static const char *open_at_end(const char *json, size_t len)
{
    char stack[64];
    int depth = 0, in_string = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = json[i];
        if (in_string) {
            if (ch == '\\') i++;
            else if (ch == '"') in_string = 0;
        } else if (ch == '"') in_string = 1;
        else if (ch == '{' || ch == '[') {
            if (depth < (int)sizeof stack) stack[depth] = ch;
            depth++;
        } else if ((ch == '}' || ch == ']') && depth > 0) depth--;
    }
    if (in_string) return "a string";
    if (depth == 0) return "a value";
    char top = depth <= (int)sizeof stack ? stack[depth - 1] : '{';
    return top == '{' ? "an object" : "an array";
}

lc_status lc_tf_parse(lc_device *device, const char *json, const char *name, lc_tf **out)
{
    if (!name) name = "transfer function";
    if (!out) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_parse: out is NULL");
    *out = NULL;
    if (!json) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_parse: json is NULL");
    parse_ctx c = {device, name};
    size_t blank = strspn(json, " \t\r\n");
    if (!json[blank])
        return lci_error(device, LC_ERROR_FORMAT, "%s: %s, expected a JSON object", name,
                         blank ? "only white space" : "empty file");
    json_tokener *tok = json_tokener_new();
    if (!tok) return lci_error(device, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    size_t len = strlen(json);
    json_object *root = json_tokener_parse_ex(tok, json, (int)len);
    enum json_tokener_error jerr = json_tokener_get_error(tok);
    size_t off = json_tokener_get_parse_end(tok);
    json_tokener_free(tok);
    if (!root || jerr != json_tokener_success) {
        int line = 1;
        for (size_t i = 0; i < off && i < len; i++) line += json[i] == '\n';
        if (root) json_object_put(root);
        if (jerr == json_tokener_continue) /* the text ended inside something */
            return lci_error(device, LC_ERROR_FORMAT, "%s:%d: the JSON ends at byte %zu inside %s (truncated?)", name,
                             line, len, open_at_end(json, len));
        return lci_error(device, LC_ERROR_FORMAT, "%s:%d: invalid JSON: %s", name, line,
                         jerr == json_tokener_success ? "unexpected end" : json_tokener_error_desc(jerr));
    }
    lc_tf_field fields[LC_MAX_FIELDS];
    float *keep[2 * LC_MAX_FIELDS] = {0};
    int nf = 0;
    lc_status s = LC_OK;
    json_object *arr = NULL, *range = NULL, *rgbp = NULL;
    if (json_object_is_type(root, json_type_array) ||
        (json_object_is_type(root, json_type_object) && json_object_object_get_ex(root, "RGBPoints", &rgbp))) {
        s = read_paraview(&c, root, out);
        json_object_put(root);
        return s;
    } else if (!json_object_is_type(root, json_type_object)) {
        s = lci_error(device, LC_ERROR_FORMAT,
                      "%s: the top level must be a JSON object (SPEC.md) or an array (a ParaView preset)", name);
    } else if (json_object_object_get_ex(root, "fields", &arr)) {
        if (!json_object_is_type(arr, json_type_array) || json_object_array_length(arr) < 1 ||
            json_object_array_length(arr) > LC_MAX_FIELDS) {
            s = lci_error(device, LC_ERROR_FORMAT, "%s: \"fields\" must be an array of 1 to %d transfer functions",
                          name, LC_MAX_FIELDS);
        } else {
            nf = (int)json_object_array_length(arr);
            for (int f = 0; f < nf && s == LC_OK; f++)
                s = read_field(&c, f, json_object_array_get_idx(arr, (size_t)f), &fields[f], &keep[2 * f],
                               &keep[2 * f + 1]);
            /* a top-level range applies to fields without their own */
            if (s == LC_OK && json_object_object_get_ex(root, "range", &range) &&
                json_object_is_type(range, json_type_array) && json_object_array_length(range) == 2) {
                for (int f = 0; f < nf; f++)
                    if (!fields[f].has_range) {
                        fields[f].has_range = 1;
                        fields[f].range[0] = (float)json_object_get_double(json_object_array_get_idx(range, 0));
                        fields[f].range[1] = (float)json_object_get_double(json_object_array_get_idx(range, 1));
                    }
            }
        }
    } else {
        nf = 1;
        s = read_field(&c, 0, root, &fields[0], &keep[0], &keep[1]);
    }
    if (s == LC_OK) s = create(device, name, fields, nf, out);
    for (int i = 0; i < 2 * LC_MAX_FIELDS; i++) free(keep[i]);
    json_object_put(root);
    return s;
}

#else
lc_status lc_tf_parse(lc_device *device, const char *json, const char *name, lc_tf **out)
{
    if (!name) name = "transfer function";
    if (!out) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_parse: out is NULL");
    *out = NULL;
    if (!json) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_parse: json is NULL");
    return lci_missing(device, name, "a JSON transfer function", LCI_FEATURE_JSON);
}
#endif

lc_status lc_tf_load(lc_device *device, const char *path, lc_tf **out)
{
    if (!out) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_load: out is NULL");
    *out = NULL;
    if (!path) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_load: path is NULL");
    FILE *fp;
    lc_status os = lci_open_regular(device, path, NULL, &fp, NULL); /* not a directory or FIFO */
    if (os != LC_OK) return os;
    char *buf = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (n + 4096 + 1 > cap) {
            cap = cap ? cap * 2 : 8192;
            if (cap > (64u << 20)) {
                free(buf);
                fclose(fp);
                return lci_error(device, LC_ERROR_FORMAT, "%s: larger than 64 MiB; not a transfer function", path);
            }
            char *nb = realloc(buf, cap);
            if (!nb) {
                free(buf);
                fclose(fp);
                return lci_error(device, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            }
            buf = nb;
        }
        size_t r = fread(buf + n, 1, cap - n - 1, fp);
        n += r;
        if (r == 0) break;
    }
    int err = ferror(fp);
    fclose(fp);
    if (err) {
        free(buf);
        return lci_error(device, LC_ERROR_IO, "%s: read error", path);
    }
    buf[n] = '\0';
    const char *nul = memchr(buf, 0, n);
    if (nul) {
        int line = 1;
        for (const char *q = buf; q < nul; q++) line += *q == '\n';
        lc_status e = lci_error(device, LC_ERROR_FORMAT, "%s:%d: a NUL byte at byte %zu (not a JSON text file?)", path,
                                line, (size_t)(nul - buf));
        free(buf);
        return e;
    }
    lc_status s = lc_tf_parse(device, buf, path, out);
    free(buf);
    return s;
}

/* ---- presets */

#include "host/api/colormaps_data.h"

typedef struct colormap {
    const char *name;
    const float *points; /* [v, r, g, b] */
    int n;
} colormap;

#define CM(name, arr) {name, arr, (int)(sizeof arr / sizeof arr[0] / 4)}
static const float heat[] = {0.0f, 0.05f, 0.0f, 0.2f, 0.35f, 0.6f, 0.05f, 0.1f, 0.65f, 1.0f, 0.45f, 0.0f,
                             1.0f, 1.0f, 1.0f, 0.8f};
static const float cool[] = {0.0f, 0.0f, 0.1f, 0.3f, 0.5f, 0.1f, 0.5f, 0.9f, 1.0f, 0.8f, 1.0f, 1.0f};
static const float gray[] = {0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f, 1.0f};
static const float warm[] = {0.0f, 0.6f, 0.1f, 0.05f, 0.5f, 1.0f, 0.5f, 0.1f, 1.0f, 1.0f, 0.95f, 0.6f};
/* "demo" (warm and cool alternating by field) is listed but built apart */
static const colormap maps[] = {
    CM("heat", heat),        CM("cool", cool),       CM("gray", gray),       {"demo", warm, 3},
    CM("viridis", cm_viridis), CM("inferno", cm_inferno), CM("magma", cm_magma), CM("plasma", cm_plasma),
    CM("cool-warm", cm_cool_warm), CM("grayscale", cm_grayscale),
};
#define NMAPS ((int)(sizeof maps / sizeof maps[0]))

const char *lc_tf_preset_name(int index) { return index >= 0 && index < NMAPS ? maps[index].name : NULL; }

lc_status lci_colormap(lc_device *device, const char *name, const float **points, int *n)
{
    for (int i = 0; name && i < NMAPS; i++)
        if (!strcmp(name, maps[i].name)) return *points = maps[i].points, *n = maps[i].n, LC_OK;
    char known[256] = "";
    for (int i = 0; i < NMAPS; i++)
        snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", i ? ", " : "", maps[i].name);
    return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "unknown colour map '%s' (known: %s)", name ? name : "(null)",
                     known);
}

lc_status lc_tf_preset(lc_device *device, const char *name, int nfields, float max_tau, lc_tf **out)
{
    if (!out) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_preset: out is NULL");
    *out = NULL;
    if (!name) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_preset: name is NULL");
    if (!(max_tau >= 0.0f) || !isfinite(max_tau))
        return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_preset: max_tau = %g, expected a finite value >= 0",
                         (double)max_tau);
    float op[] = {0.0f, 0.0f, 0.1f, 0.0f, 1.0f, max_tau};
    lc_tf_field f[LC_MAX_FIELDS];
    memset(f, 0, sizeof f);
    if (nfields < 1 || nfields > LC_MAX_FIELDS)
        return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_tf_preset: %d fields, expected 1 to %d", nfields,
                         LC_MAX_FIELDS);
    const float *pts;
    int n;
    lc_status s = lci_colormap(device, name, &pts, &n);
    if (s != LC_OK) return s;
    for (int i = 0; i < nfields; i++) {
        f[i].opacity = op;
        f[i].nopacity = 3;
        f[i].color = pts, f[i].ncolor = n;
        if (!strcmp(name, "demo") && i % 2) f[i].color = cool, f[i].ncolor = 3; /* field 0 warm, 1 cool, ... */
    }
    return create(device, "lc_tf_preset", f, nfields, out);
}
