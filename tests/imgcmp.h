/* The one image comparer of the tests: two premultiplied float RGBA images of
 * w x h, SPEC.md "Tolerances between paths" (max per-channel difference
 * <= 2/255, PSNR >= 50 dB). Any NaN or Inf in either image fails. Plain C,
 * no lanecast code. */
#ifndef LC_TEST_IMGCMP_H
#define LC_TEST_IMGCMP_H

#define IMGCMP_MAX_DIFF_255 2.0 /* SPEC.md default tolerances */
#define IMGCMP_MIN_PSNR_DB 50.0

typedef struct imgcmp_result {
    double max_diff_255;  /* max |got - want| over channels, in 1/255 units (finite values only) */
    int worst_x, worst_y; /* its pixel (-1 when the images agree exactly) */
    int worst_channel;    /* 0..3 = r, g, b, a */
    double psnr_db;       /* 10 log10(1 / MSE) over all 4 w h values (peak 1); INFINITY when equal */
    long ndiff;           /* pixels with some channel differing by more than count_above_255 */
    long nonfinite;       /* NaN or Inf values in got and want together */
    int bad_x, bad_y;     /* first non-finite value (-1 when none) */
    int bad_channel;
    int bad_in_want;      /* 0: it is in got, 1: in want */
    double bad_value;
} imgcmp_result;

/* Fills r; pixels with a non-finite value in either image are counted in
 * nonfinite and left out of max_diff_255, psnr_db and ndiff. Returns 0, or -1
 * when w or h < 1 or a pointer is NULL. */
int imgcmp_stats(const float *got, const float *want, int w, int h, double count_above_255, imgcmp_result *r);

/* Compares, prints one line ("imgcmp <label>: PASS|FAIL ..."), returns 0 when
 * no value is NaN or Inf, max diff <= max_diff_255 and PSNR >= min_psnr_db
 * (0 or below for either: the SPEC.md default; but see IMGCMP_NO_PSNR_BOUND). On failure, when diff_dir is not
 * NULL, writes <diff_dir>/<label>.diff.ppm: got | want | |difference| x 16
 * (non-finite values magenta), premultiplied colour over black, and names it
 * in the line. Returns 1 on failure, -1 on bad arguments. */
int imgcmp_check(const char *label, const float *got, const float *want, int w, int h, double max_diff_255,
                 double min_psnr_db, const char *diff_dir);

/* Bounds for a check that has only one of the two: IMGCMP_NO_MAX_BOUND as
 * max_diff_255 (any finite difference), IMGCMP_NO_PSNR_BOUND as min_psnr_db
 * (any PSNR). NaN and Inf fail regardless. */
#define IMGCMP_NO_MAX_BOUND 1e300
#define IMGCMP_NO_PSNR_BOUND (-1e300)

/* imgcmp_check with two more arguments: quiet != 0 prints the line (and writes
 * the diff image) only on failure, for tests that compare thousands of
 * images; r, when not NULL, receives the statistics (for a test's own
 * summary of its worst case). Same return values. */
int imgcmp_check_ex(const char *label, const float *got, const float *want, int w, int h, double max_diff_255,
                    double min_psnr_db, const char *diff_dir, int quiet, imgcmp_result *r);

/* A test's worst case over many checks: the largest max difference and the
 * lowest PSNR seen (over finite pixels), the images counted and those with
 * NaN or Inf. Start from IMGCMP_WORST_INIT. */
typedef struct imgcmp_worst {
    double max_diff_255, psnr_db;
    long count, nonfinite;
} imgcmp_worst;
#define IMGCMP_WORST_INIT {0.0, 1e300, 0, 0}

void imgcmp_worst_add(imgcmp_worst *w, const imgcmp_result *r);
/* "worst <label>: max X/255, PSNR Y dB over N images (M with NaN/Inf)" */
void imgcmp_worst_print(const char *label, const imgcmp_worst *w);

#endif
