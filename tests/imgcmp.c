/* Image comparer (see imgcmp.h). */
#include "imgcmp.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char chan_name[4] = {'r', 'g', 'b', 'a'};

static void note_bad(imgcmp_result *r, int x, int y, int c, int in_want, double v)
{
    if (r->nonfinite++ == 0) r->bad_x = x, r->bad_y = y, r->bad_channel = c, r->bad_in_want = in_want, r->bad_value = v;
}

int imgcmp_stats(const float *got, const float *want, int w, int h, double count_above_255, imgcmp_result *r)
{
    if (!got || !want || !r || w < 1 || h < 1) return -1;
    *r = (imgcmp_result){0.0, -1, -1, 0, INFINITY, 0, 0, -1, -1, 0, 0, 0.0};
    double se = 0.0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = 4 * ((size_t)y * (size_t)w + (size_t)x);
            int finite = 1, over = 0;
            for (int c = 0; c < 4; c++) {
                if (!isfinite(got[i + c])) note_bad(r, x, y, c, 0, got[i + c]), finite = 0;
                if (!isfinite(want[i + c])) note_bad(r, x, y, c, 1, want[i + c]), finite = 0;
            }
            if (!finite) continue;
            for (int c = 0; c < 4; c++) {
                double d = fabs((double)got[i + c] - (double)want[i + c]);
                se += d * d;
                if (d * 255.0 > count_above_255) over = 1;
                if (d * 255.0 > r->max_diff_255)
                    r->max_diff_255 = d * 255.0, r->worst_x = x, r->worst_y = y, r->worst_channel = c;
            }
            r->ndiff += over;
        }
    double mse = se / (4.0 * (double)w * (double)h);
    r->psnr_db = mse > 0.0 ? 10.0 * log10(1.0 / mse) : INFINITY;
    return 0;
}

static unsigned char to8(double v)
{
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    return (unsigned char)floor(255.0 * v + 0.5);
}

/* got | want | |got - want| x 16 (colour of the larger of the rgb and alpha
 * differences), non-finite magenta; binary PPM (P6). */
static int write_diff(const char *path, const float *got, const float *want, int w, int h)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    fprintf(f, "P6\n%d %d\n255\n", 3 * w, h);
    unsigned char *row = malloc((size_t)9 * (size_t)w);
    if (!row) {
        fclose(f);
        return -1;
    }
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            const float *g = got + 4 * ((size_t)y * (size_t)w + (size_t)x);
            const float *t = want + 4 * ((size_t)y * (size_t)w + (size_t)x);
            int bad = 0;
            for (int c = 0; c < 4; c++) bad |= !isfinite(g[c]) || !isfinite(t[c]);
            double da = fabs((double)g[3] - t[3]);
            for (int c = 0; c < 3; c++) {
                unsigned char *px = row + 3 * (size_t)x + (size_t)c;
                double d = fmax(fabs((double)g[c] - t[c]), da);
                px[0] = isfinite(g[c]) ? to8(g[c]) : (c == 1 ? 0 : 255);
                px[3 * (size_t)w] = isfinite(t[c]) ? to8(t[c]) : (c == 1 ? 0 : 255);
                px[6 * (size_t)w] = bad ? (c == 1 ? 0 : 255) : to8(16.0 * d);
            }
        }
        fwrite(row, 1, (size_t)9 * (size_t)w, f);
    }
    free(row);
    return fclose(f) == 0 ? 0 : -1;
}

static void diff_path(char *out, size_t n, const char *dir, const char *label)
{
    char name[128];
    size_t j = 0;
    for (const char *s = label; *s && j + 1 < sizeof name; s++) {
        char ch = *s;
        int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '-' ||
                 ch == '.';
        name[j++] = ok ? ch : '_';
    }
    name[j] = 0;
    snprintf(out, n, "%s/%s.diff.ppm", dir, j ? name : "image");
}

int imgcmp_check_ex(const char *label, const float *got, const float *want, int w, int h, double max_diff_255,
                    double min_psnr_db, const char *diff_dir, int quiet, imgcmp_result *out)
{
    imgcmp_result r;
    double tol = max_diff_255 > 0.0 ? max_diff_255 : IMGCMP_MAX_DIFF_255;
    double minp = min_psnr_db == IMGCMP_NO_PSNR_BOUND ? -INFINITY
                  : min_psnr_db > 0.0                 ? min_psnr_db
                                                      : IMGCMP_MIN_PSNR_DB;
    if (!label) label = "image";
    if (imgcmp_stats(got, want, w, h, tol, &r)) {
        printf("imgcmp %s: FAIL bad arguments (%dx%d)\n", label, w, h);
        return -1;
    }
    if (out) *out = r;
    int fail = r.nonfinite > 0 || !(r.max_diff_255 <= tol) || !(r.psnr_db >= minp);
    if (quiet && !fail) return 0;
    char psnr[32], bad[160] = "", file[600] = "";
    if (isinf(r.psnr_db)) snprintf(psnr, sizeof psnr, "inf");
    else snprintf(psnr, sizeof psnr, "%.1f", r.psnr_db);
    if (r.nonfinite)
        snprintf(bad, sizeof bad, " %ld NaN/Inf values, first %g in %s at (%d,%d) %c;", r.nonfinite, r.bad_value,
                 r.bad_in_want ? "want" : "got", r.bad_x, r.bad_y, chan_name[r.bad_channel]);
    if (fail && diff_dir) {
        char path[560];
        diff_path(path, sizeof path, diff_dir, label);
        if (write_diff(path, got, want, w, h) == 0) snprintf(file, sizeof file, "; diff %s", path);
        else snprintf(file, sizeof file, "; could not write %s", path);
    }
    char where[48] = "";
    if (r.worst_x >= 0) snprintf(where, sizeof where, " at (%d,%d) %c", r.worst_x, r.worst_y, chan_name[r.worst_channel]);
    printf("imgcmp %s: %s %dx%d%s max %.3f/255 (limit %.3g)%s, PSNR %s dB (min %.3g), %ld px over limit%s%s\n", label,
           fail ? "FAIL" : "PASS", w, h, bad, r.max_diff_255, tol, where, psnr, minp, r.ndiff,
           r.nonfinite ? " (finite pixels only)" : "", file);
    return fail;
}

int imgcmp_check(const char *label, const float *got, const float *want, int w, int h, double max_diff_255,
                 double min_psnr_db, const char *diff_dir)
{
    return imgcmp_check_ex(label, got, want, w, h, max_diff_255, min_psnr_db, diff_dir, 0, NULL);
}

void imgcmp_worst_add(imgcmp_worst *w, const imgcmp_result *r)
{
    if (r->max_diff_255 > w->max_diff_255) w->max_diff_255 = r->max_diff_255;
    if (r->psnr_db < w->psnr_db) w->psnr_db = r->psnr_db;
    w->count++;
    w->nonfinite += r->nonfinite > 0;
}

void imgcmp_worst_print(const char *label, const imgcmp_worst *w)
{
    if (w->count == 0) {
        printf("worst %s: no images compared\n", label);
        return;
    }
    char psnr[32];
    if (w->psnr_db >= 1e300) snprintf(psnr, sizeof psnr, "inf");
    else snprintf(psnr, sizeof psnr, "%.1f", w->psnr_db);
    printf("worst %s: max %.3f/255, PSNR %s dB over %ld images (%ld with NaN/Inf)\n", label, w->max_diff_255, psnr,
           w->count, w->nonfinite);
}
