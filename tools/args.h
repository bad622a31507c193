/* Command-line parsing helpers: each prints one line naming the flag and the
 * bad value, and returns -1. */
#ifndef LC_CLI_ARGS_H
#define LC_CLI_ARGS_H

#include "lanecast/lanecast.h"

/* A number that, as a float, lies in [lo, hi] (arg_float_below: [lo, hi)). */
int arg_float(const char *cmd, const char *flag, const char *s, float lo, float hi, float *out);
int arg_float_below(const char *cmd, const char *flag, const char *s, float lo, float hi, float *out);
/* n comma-separated integers in [lo, hi], parsed as integers (no float
 * rounding: 16777217 stays 16777217) with overflow checks. */
int arg_ints(const char *cmd, const char *flag, const char *s, int n, long long lo, long long hi, long long *out);
/* A memory size as the library's max_memory option takes it ("8G", "512M",
 * bytes): 0 ok, -1 (message printed) not one. */
int arg_memory(const char *cmd, const char *flag, const char *s);
/* The same, with the size in bytes in *out. */
int arg_memory_bytes(const char *cmd, const char *flag, const char *s, uint64_t *out);
int arg_int(const char *cmd, const char *flag, const char *s, long lo, long hi, int *out);
int arg_size_t(const char *cmd, const char *flag, const char *s, size_t *out);
int arg_vec3(const char *cmd, const char *flag, const char *s, lc_vec3 *out);
/* KA,KD,KS[,P]: the lighting coefficients (>= 0) and the integer Phong
 * exponent P in 1..256 (16 when omitted). */
int arg_lighting(const char *cmd, const char *flag, const char *s, lc_lighting *out);
int arg_pair(const char *cmd, const char *flag, const char *s, float out[2]);
int arg_size(const char *cmd, const char *flag, const char *s, int *w, int *h);
/* px,py,pz,nx,ny,nz: a point and a non-zero normal. */
int arg_plane(const char *cmd, const char *flag, const char *s, lc_plane *out);
/* The value of flag argv[*i] (advancing *i), or NULL after a message. */
const char *arg_value(const char *cmd, int argc, char **argv, int *i);

#endif
