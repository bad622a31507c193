#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "args.h"

const char *arg_value(const char *cmd, int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value\n", cmd, argv[*i]);
        return NULL;
    }
    return argv[++*i];
}

/* The value as the float it becomes, compared with the float bounds in
 * float (a double compared with a float bound would refuse the bound
 * itself: "1e-30 is outside [1e-30, ...]"); hi_open: hi itself is refused. */
static int float_in(const char *cmd, const char *flag, const char *s, float lo, float hi, int hi_open, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || !isfinite(v) || (errno == ERANGE && v != 0.0)) {
        fprintf(stderr, "%s: %s: '%s' is not a number\n", cmd, flag, s);
        return -1;
    }
    float f = (float)v;
    if (!isfinite(f) || f < lo || f > hi || (hi_open && f >= hi) || (v != 0.0 && f == 0.0f)) {
        fprintf(stderr, "%s: %s: %s is outside [%g, %g%c\n", cmd, flag, s, (double)lo, (double)hi, hi_open ? ')' : ']');
        return -1;
    }
    *out = f;
    return 0;
}

int arg_float(const char *cmd, const char *flag, const char *s, float lo, float hi, float *out)
{
    return float_in(cmd, flag, s, lo, hi, 0, out);
}

int arg_float_below(const char *cmd, const char *flag, const char *s, float lo, float hi, float *out)
{
    return float_in(cmd, flag, s, lo, hi, 1, out);
}

int arg_int(const char *cmd, const char *flag, const char *s, long lo, long hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end || errno == ERANGE) {
        fprintf(stderr, "%s: %s: '%s' is not an integer\n", cmd, flag, s);
        return -1;
    }
    if (v < lo || v > hi) {
        fprintf(stderr, "%s: %s: %ld is outside [%ld, %ld]\n", cmd, flag, v, lo, hi);
        return -1;
    }
    *out = (int)v;
    return 0;
}

int arg_size_t(const char *cmd, const char *flag, const char *s, size_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (end == s || *end || errno == ERANGE || s[0] == '-' || v == 0) {
        fprintf(stderr, "%s: %s: '%s' is not a positive count\n", cmd, flag, s);
        return -1;
    }
    *out = (size_t)v;
    return 0;
}

static int floats(const char *s, float *v, int n)
{
    const char *p = s;
    for (int k = 0; k < n; k++) {
        char *end;
        errno = 0;
        double x = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(x)) return -1;
        v[k] = (float)x;
        p = end;
        if (k + 1 < n) {
            if (*p != ',') return -1;
            p++;
        }
    }
    return *p ? -1 : 0;
}

int arg_vec3(const char *cmd, const char *flag, const char *s, lc_vec3 *out)
{
    float v[3];
    if (floats(s, v, 3)) {
        fprintf(stderr, "%s: %s: expected x,y,z (three numbers), got '%s'\n", cmd, flag, s);
        return -1;
    }
    out->x = v[0], out->y = v[1], out->z = v[2];
    return 0;
}

int arg_lighting(const char *cmd, const char *flag, const char *s, lc_lighting *out)
{
    float v[4] = {0, 0, 0, 16};
    int n = 0;
    for (const char *c = s; *c; c++) n += *c == ',';
    if ((n != 2 && n != 3) || floats(s, v, n + 1)) {
        fprintf(stderr, "%s: %s: expected KA,KD,KS or KA,KD,KS,P (three or four numbers), got '%s'\n", cmd, flag, s);
        return -1;
    }
    for (int k = 0; k < 3; k++)
        if (!(v[k] >= 0.0f)) {
            fprintf(stderr, "%s: %s: %s is %g; the coefficients must be >= 0 (got '%s')\n", cmd, flag,
                    k == 0 ? "KA" : k == 1 ? "KD" : "KS", (double)v[k], s);
            return -1;
        }
    if (!(v[3] >= 1.0f && v[3] <= 256.0f) || v[3] != (float)(int)v[3]) {
        fprintf(stderr, "%s: %s: the exponent P must be an integer from 1 to 256 (got '%s')\n", cmd, flag, s);
        return -1;
    }
    out->ka = v[0], out->kd = v[1], out->ks = v[2], out->phong_exp = (int)v[3];
    return 0;
}

int arg_pair(const char *cmd, const char *flag, const char *s, float out[2])
{
    if (floats(s, out, 2)) {
        fprintf(stderr, "%s: %s: expected two numbers a,b, got '%s'\n", cmd, flag, s);
        return -1;
    }
    return 0;
}

int arg_size(const char *cmd, const char *flag, const char *s, int *w, int *h)
{
    char *end;
    long a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X')) goto bad;
    const char *p = end + 1;
    long b = strtol(p, &end, 10);
    if (end == p || *end) goto bad;
    if (a < 1 || b < 1 || a > 32768 || b > 32768) {
        fprintf(stderr, "%s: %s: %s is outside 1x1 to 32768x32768\n", cmd, flag, s);
        return -1;
    }
    *w = (int)a, *h = (int)b;
    return 0;
bad:
    fprintf(stderr, "%s: %s: expected WIDTHxHEIGHT (e.g. 1024x768), got '%s'\n", cmd, flag, s);
    return -1;
}

int arg_plane(const char *cmd, const char *flag, const char *s, lc_plane *out)
{
    float v[6];
    if (floats(s, v, 6)) {
        fprintf(stderr, "%s: %s: expected px,py,pz,nx,ny,nz (a point and a normal: six numbers), got '%s'\n", cmd, flag,
                s);
        return -1;
    }
    if (v[3] == 0.0f && v[4] == 0.0f && v[5] == 0.0f) {
        fprintf(stderr, "%s: %s: the normal (%s) is zero\n", cmd, flag, s);
        return -1;
    }
    out->point = (lc_vec3){v[0], v[1], v[2]};
    out->normal = (lc_vec3){v[3], v[4], v[5]};
    return 0;
}

int arg_ints(const char *cmd, const char *flag, const char *s, int n, long long lo, long long hi, long long *out)
{
    const char *p = s;
    for (int k = 0; k < n; k++) {
        char *end;
        errno = 0;
        long long v = strtoll(p, &end, 10); /* integers as integers: never through a float */
        const char *why = NULL;
        if (end == p) why = "is not an integer";
        else if (errno == ERANGE || v < lo || v > hi) why = "is out of range";
        else if (k + 1 < n ? *end != ',' : *end != '\0') why = k + 1 < n ? "is not followed by ','" : "has junk after it";
        if (why) {
            fprintf(stderr, "%s: %s: '%s': value %d %s (expected %d comma-separated integers from %lld to %lld)\n", cmd,
                    flag, s, k + 1, why, n, lo, hi);
            return -1;
        }
        out[k] = v;
        p = end + 1;
    }
    return 0;
}

int arg_memory(const char *cmd, const char *flag, const char *s)
{
    uint64_t b;
    return arg_memory_bytes(cmd, flag, s, &b);
}

int arg_memory_bytes(const char *cmd, const char *flag, const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    int ok = end != s && s[0] >= '0' && s[0] <= '9' && isfinite(v) && v > 0 && !errno;
    double mul = 1.0;
    if (ok && *end && strchr("kKmMgGtT", *end)) mul = pow(1024.0, (double)(strchr("kmgt", tolower(*end)) - "kmgt" + 1)), end++;
    if (ok && (!strcmp(end, "iB") || !strcmp(end, "ib"))) end += 2;
    else if (ok && (*end == 'B' || *end == 'b')) end++;
    if (!ok || *end) {
        fprintf(stderr, "%s: %s: '%s' is not a size (bytes, or with K, M, G, T: e.g. 512M, 8G)\n", cmd, flag, s);
        return -1;
    }
    double b = floor(v * mul);
    *out = b >= 9.2e18 ? (uint64_t)9.2e18 : b < 1.0 ? 1 : (uint64_t)b;
    return 0;
}
