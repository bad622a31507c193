/* Fuzzing regressions (issue 13, docs/FUZZING.md): every input in
 * tests/fuzz_regress/ once crashed, aborted or tripped a sanitizer in a
 * harness of fuzz/; each must now load to a clean error (a status, one
 * message, no volume) through the public API, as the harness does it. The
 * file name says which harness: HARNESS-what, with the layouts of
 * fuzz/fuzz_load.c (a first line of options for the raw formats and HDF5, a
 * first line with the companion's length for DCD + PSF; tf-*: JSON TFs).
 * In the sanitizer build (CI) a memory error fails the test too.
 * expect.txt may name, per file ("FILE: TEXT"), text the message must hold
 * (for findings that were slow or huge rather than crashes: the error must
 * come from the early check), or "(loads)" for a valid input that crashed
 * and must now load.
 * usage: test_fuzz_regress REGRESS_DIR TMP_DIR */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lanecast/lanecast.h"

/* fuzz/meson.build's harnesses: name, format, the input file's extension,
 * layout (0 plain, 1 options, 2 companion) */
static const struct {
    const char *name, *format, *ext;
    int layout;
} harness[] = {
    {"xyz", "xyz", ".xyz", 0},
    {"pdb", "pdb", ".pdb", 0},
    {"gro", "gro", ".gro", 0},
    {"mmcif", "mmcif", ".cif", 0},
    {"csv", "csv", ".csv", 0},
    {"lammps", "lammps", ".lammpstrj", 0},
    {"gadget", "gadget", ".gadget", 0},
    {"dcd_psf", "dcd", ".dcd", 2},
    {"xtc", "xtc", ".xtc", 0},
    {"xtc_top", "xtc", ".xtc", 2},
    {"trr", "trr", ".trr", 0},
    {"ncdf", "ncdf", ".nc", 0},
    {"raw_particles", "raw-particles", ".f32", 1},
    {"nrrd", "nrrd", ".nrrd", 0},
    {"metaimage", "metaimage", ".mha", 0},
    {"raw_volume", "raw-volume", ".raw", 1},
    {"nifti", "nifti", ".nii", 0},
    {"vtk", "vtk", ".vtk", 0},
    {"rbf_text", "rbf", ".rbf", 0},
    {"rbf_binary", "rbf-binary", ".rbf", 0},
    {"hdf5", "hdf5", ".h5", 1},
    {"dicom", "dicom", ".dcm", 0},
};

#if defined(__SANITIZE_ADDRESS__)
#define SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANITIZED 1
#endif
#endif
#ifndef SANITIZED
#define SANITIZED 0
#endif

static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = len >= 0 ? malloc((size_t)len + 1) : NULL;
    if (b && fread(b, 1, (size_t)len, f) != (size_t)len) free(b), b = NULL;
    fclose(f);
    if (b) b[len] = 0, *n = (size_t)len;
    return b;
}

static int put(const char *path, const unsigned char *p, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    int ok = fwrite(p, 1, n, f) == n;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* One input: 1 when it fails cleanly. */
static int run(lc_device *dev, const char *tmp, const char *name, unsigned char *d, size_t n, char *why,
               size_t wn)
{
    if (!strncmp(name, "tf-", 3)) {
        lc_tf *tf = NULL;
        lc_status s = lc_tf_parse(dev, (const char *)d, name, &tf);
        snprintf(why, wn, "%s: %s", lc_status_string(s), lc_last_error());
        lc_tf_destroy(tf);
        return s != LC_OK && s != LC_ERROR_INTERNAL && !tf && lc_last_error()[0];
    }
    int h = -1;
    for (size_t i = 0; i < sizeof harness / sizeof harness[0]; i++) {
        size_t l = strlen(harness[i].name);
        if (!strncmp(name, harness[i].name, l) && name[l] == '-') h = (int)i;
    }
    if (h < 0) {
        snprintf(why, wn, "no harness named by the file name (HARNESS-what)");
        return 0;
    }
    char main_path[4200], comp_path[4200], line[256] = "";
    snprintf(main_path, sizeof main_path, "%s/fuzz-regress-input%s", tmp, harness[h].ext);
    snprintf(comp_path, sizeof comp_path, "%s/fuzz-regress-companion", tmp);
    lc_load_desc desc = {.format = harness[h].format};
    lc_option opts[8];
    int nopts = 0;
    if (harness[h].layout) {
        unsigned char *nl = memchr(d, '\n', n < 255 ? n : 255);
        if (!nl) {
            snprintf(why, wn, "not in the harness's layout (no first line)");
            return 0;
        }
        size_t len = (size_t)(nl - d);
        memcpy(line, d, len);
        line[len] = 0;
        d += len + 1, n -= len + 1;
    }
    if (harness[h].layout == 1) {
        for (char *tok = strtok(line, " "); tok && nopts < 8; tok = strtok(NULL, " ")) {
            char *eq = strchr(tok, '=');
            if (!eq) continue;
            *eq = 0;
            opts[nopts++] = (lc_option){tok, eq + 1};
        }
        desc.options = opts, desc.noptions = nopts;
    } else if (harness[h].layout == 2) {
        size_t clen = strtoul(line, NULL, 10);
        if (clen > n || put(comp_path, d, clen) != 0) {
            snprintf(why, wn, "bad companion length");
            return 0;
        }
        desc.companion = comp_path;
        d += clen, n -= clen;
    }
    if (put(main_path, d, n) != 0) {
        snprintf(why, wn, "cannot write %s", main_path);
        return 0;
    }
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, main_path, &desc, &v);
    snprintf(why, wn, "%s: %s", lc_status_string(s), lc_last_error());
    lc_volume_destroy(v);
    remove(main_path), remove(comp_path);
    return s != LC_OK && s != LC_ERROR_INTERNAL && !v && lc_last_error()[0];
}

/* The text expect.txt in dir names for file, or NULL. */
static const char *expected(const char *dir, const char *file)
{
    static char line[512];
    char path[4200];
    snprintf(path, sizeof path, "%s/expect.txt", dir);
    FILE *f = fopen(path, "r");
    const char *found = NULL;
    size_t l = strlen(file);
    while (f && !found && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = 0;
        if (!strncmp(line, file, l) && line[l] == ':' && line[l + 1] == ' ') found = line + l + 2;
    }
    if (f) fclose(f);
    return found;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_fuzz_regress REGRESS_DIR TMP_DIR\n");
        return 2;
    }
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = LC_TARGET_SCALAR, .threads = 1}, &dev) != LC_OK) return 1;
    DIR *dir = opendir(argv[1]);
    CHECK(dir != NULL, "open %s", argv[1]);
    int seen = 0;
    for (struct dirent *e; dir && (e = readdir(dir));) {
        if (e->d_name[0] == '.' || !strcmp(e->d_name, "README.md") || !strcmp(e->d_name, "expect.txt")) continue;
        /* "-nosan-": inputs that make libhdf5 allocate without end; the guard
           process's address-space limit stops it, and AddressSanitizer's
           shadow memory rules that limit out (host/formats/guard.c) */
        if (SANITIZED && strstr(e->d_name, "-nosan-")) {
            printf("skip %s: needs the guard's memory limit, which a sanitizer build has not\n", e->d_name);
            continue;
        }
        char path[4200], why[4800];
        snprintf(path, sizeof path, "%s/%s", argv[1], e->d_name);
        size_t n = 0;
        unsigned char *d = slurp(path, &n);
        int ok = d && run(dev, argv[2], e->d_name, d, n, why, sizeof why);
        const char *want = expected(argv[1], e->d_name);
        /* "(loads)": a valid input that crashed; it must now load (or, its
           format compiled out of this build, fail naming the package) */
        if (d && want && !strcmp(want, "(loads)")) {
            ok = !strncmp(why, "ok: ", 4) || !strncmp(why, "unsupported: ", 13);
            if (!strncmp(why, "ok: ", 4)) snprintf(why, sizeof why, "a volume");
        }
        /* a format compiled out of this build (NIfTI, HDF5) fails with its package's name instead */
        if (ok && want && strcmp(want, "(loads)") && !strstr(why, want) && strncmp(why, "unsupported: ", 13)) ok = 0;
        int loads = want && !strcmp(want, "(loads)");
        CHECK(ok, "%s (%zu bytes) %s%s%s%s: %s", e->d_name, n, loads ? "loads" : "fails cleanly",
              want && !loads ? " with '" : "", want && !loads ? want : "", want && !loads ? "'" : "",
              d ? why : "unreadable");
        free(d);
        seen++;
    }
    if (dir) closedir(dir);
    CHECK(seen > 0, "%d regression inputs", seen);
    lc_device_destroy(dev);
    return check_summary("fuzz_regress");
}
