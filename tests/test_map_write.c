/* lc_map_write (host/api/map_write.c) read back from the file formats'
 * own definitions: the .npy header (NumPy format 1.0: magic, version, a
 * dict with descr '<f4', fortran_order False and shape (H, W), padded to 64
 * bytes) and its float32 values row by row; the JSON sidecar's keys; with
 * the fits feature, cfitsio reading the image back (rows flipped: FITS's
 * first row is the bottom one) and the header keywords BTYPE, BUNIT, KERNEL,
 * CRVAL1/2, CDELT1, XMIN..YMAX; without it, the one-line error naming the
 * package. A half-written file never appears: an unwritable folder fails
 * and leaves nothing. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "check.h"
#include "lanecast/lanecast.h"
#include "lc_config.h"
#if LC_HAVE_FITS
#include <fitsio.h>
#endif

static char *slurp(const char *path, long *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *n = ftell(f);
    rewind(f);
    char *b = malloc((size_t)*n + 1);
    if (b && fread(b, 1, (size_t)*n, f) != (size_t)*n) free(b), b = NULL;
    if (b) b[*n] = 0;
    fclose(f);
    return b;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    enum { W = 5, H = 3 };
    float v[W * H];
    for (int i = 0; i < W * H; i++) v[i] = 0.25f * (float)i - 1.0f;
    lc_project_info view = {.pixel = 2.0, .extent = {-5, 5, 10, 16}, .right = {1, 0, 0}, .up = {0, 1, 0}, .view = {0, 0, -1},
                            .mass = 3.5};
    lc_map_desc d = {W, H, v, "column of mass", "Msun kpc^-2", "m4", "exact", 0, &view};
    char path[1024], side[1100];
    snprintf(path, sizeof path, "%s/tmw_map.npy", dir);
    snprintf(side, sizeof side, "%s.json", path);
    CHECK(lc_map_format(path) && lc_map_format("a.FITS") && lc_map_format("a.exr") && !lc_map_format("a.png"),
          "lc_map_format: .npy .FITS .exr yes, .png no");
    lc_status s = lc_map_write(NULL, path, &d);
    CHECK(s == LC_OK, "npy written: %s", s ? lc_last_error() : "ok");
    long n = 0;
    char *b = slurp(path, &n);
    int hl = b && n > 10 ? (unsigned char)b[8] | (unsigned char)b[9] << 8 : 0;
    CHECK(b && !memcmp(b, "\x93NUMPY\x01\x00", 8) && (10 + hl) % 64 == 0 && b[10 + hl - 1] == '\n' &&
              n == 10 + hl + (long)sizeof v,
          "npy: magic, version 1.0, header of %d bytes padded to 64, %ld bytes in all", hl, n);
    if (b && hl) {
        char hdr[512] = "";
        memcpy(hdr, b + 10, (size_t)(hl < 511 ? hl : 511));
        CHECK(strstr(hdr, "'descr': '<f4'") && strstr(hdr, "'fortran_order': False") && strstr(hdr, "'shape': (3, 5)"),
              "npy header: %s", hdr);
        CHECK(!memcmp(b + 10 + hl, v, sizeof v), "npy values: rows top to bottom, bit for bit");
    }
    free(b);
    char *j = slurp(side, &n);
    CHECK(j && strstr(j, "\"file\": \"tmw_map.npy\"") && strstr(j, "\"quantity\": \"column of mass\"") &&
              strstr(j, "\"units\": \"Msun kpc^-2\"") && strstr(j, "\"kernel\": \"m4\"") &&
              strstr(j, "\"extent\": [-5, 5, 10, 16]") && strstr(j, "\"pixel\": 2"),
          "JSON sidecar: file, quantity, units, kernel, extent, pixel");
    free(j);
    unlink(path), unlink(side);
    snprintf(path, sizeof path, "%s/tmw_map.fits", dir);
    s = lc_map_write(NULL, path, &d);
#if LC_HAVE_FITS
    CHECK(s == LC_OK, "FITS written: %s", s ? lc_last_error() : "ok");
    fitsfile *f = NULL;
    int st = 0, naxis = 0, anynul = 0;
    long ax[2] = {0, 0};
    float back[W * H];
    fits_open_file(&f, path, READONLY, &st);
    fits_get_img_dim(f, &naxis, &st);
    fits_get_img_size(f, 2, ax, &st);
    fits_read_img(f, TFLOAT, 1, W * H, NULL, back, &anynul, &st);
    int flipped = 1;
    for (int r = 0; r < H; r++)
        flipped &= !memcmp(back + r * W, v + (H - 1 - r) * W, sizeof(float) * W);
    CHECK(!st && naxis == 2 && ax[0] == W && ax[1] == H && flipped, "FITS image %ldx%ld, first row = the map's bottom row",
          ax[0], ax[1]);
    char q[FLEN_VALUE] = "", u[FLEN_VALUE] = "", k[FLEN_VALUE] = "";
    double crval1 = 0, crval2 = 0, cdelt = 0, xmax = 0, ymin = 0;
    fits_read_key(f, TSTRING, "BTYPE", q, NULL, &st);
    fits_read_key(f, TSTRING, "BUNIT", u, NULL, &st);
    fits_read_key(f, TSTRING, "KERNEL", k, NULL, &st);
    fits_read_key(f, TDOUBLE, "CRVAL1", &crval1, NULL, &st);
    fits_read_key(f, TDOUBLE, "CRVAL2", &crval2, NULL, &st);
    fits_read_key(f, TDOUBLE, "CDELT1", &cdelt, NULL, &st);
    fits_read_key(f, TDOUBLE, "XMAX", &xmax, NULL, &st);
    fits_read_key(f, TDOUBLE, "YMIN", &ymin, NULL, &st);
    CHECK(!st && !strcmp(q, "column of mass") && !strcmp(u, "Msun kpc^-2") && !strcmp(k, "m4") && crval1 == -5 &&
              crval2 == 10 && cdelt == 2 && xmax == 5 && ymin == 10,
          "FITS keywords: BTYPE '%s', BUNIT '%s', KERNEL '%s', CRVAL %g %g, CDELT1 %g, XMAX %g, YMIN %g (status %d)", q, u,
          k, crval1, crval2, cdelt, xmax, ymin, st);
    st = 0;
    fits_close_file(f, &st);
    unlink(path);
#else
    CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "libcfitsio-dev"), "FITS without cfitsio: %s",
          lc_last_error());
    CHECK(access(path, F_OK) != 0, "nothing written");
    printf("skip FITS read-back: this build lacks the fits feature (libcfitsio-dev)\n");
#endif
    s = lc_map_write(NULL, "/nonexistent-dir/m.npy", &d);
    CHECK(s == LC_ERROR_IO && access("/nonexistent-dir/m.npy", F_OK) != 0, "unwritable folder: %s", lc_last_error());
    s = lc_map_write(NULL, "m.png", &d);
    CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "not a float-map format"), "png: %s", lc_last_error());
    d.width = 0;
    CHECK(lc_map_write(NULL, "m.npy", &d) == LC_ERROR_INVALID_ARGUMENT, "size 0: %s", lc_last_error());
    return check_summary("test_map_write");
}
