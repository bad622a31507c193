/* Determinism (issue 13): on every target this CPU runs, each scene of
 * scenes3.h (particles, grid, RBF set) renders to the same bytes for every
 * thread count (1, 2, 4), tile size (8, 13, 32, 64: 13 is no multiple of
 * the packet side, so packets are cut differently) and repeat, and in a
 * second process (this program run again with --hashes: other addresses,
 * other allocation alignment). Targets may differ from each other (SPEC.md
 * tolerances, checked by the image tests), never from themselves.
 * usage: test_determinism [--hashes] */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scenes3.h"

#define W 72
#define H 56

static uint64_t fnv(const void *p, size_t n)
{
    const unsigned char *b = p;
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* Renders scene k on a device of target t with the given threads and tile;
 * 0 ok. */
static int render(lc_target t, int threads, const scenes3 *s, int k, int tile, float *img)
{
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = t, .threads = threads}, &dev) != LC_OK) return -1;
    lc_render_desc d = scenes3_desc(s, k, W, H, tile);
    lc_status st = lc_render(dev, &d, img, NULL);
    lc_device_destroy(dev);
    return st == LC_OK ? 0 : -1;
}

static int usable(lc_target t) { return lc_target_compiled(t) && lc_target_supported(t); }

int main(int argc, char **argv)
{
    int hashes_only = argc > 1 && !strcmp(argv[1], "--hashes");
    lc_device *owner = NULL;
    scenes3 *s = malloc(sizeof *s);
    float *ref = malloc(sizeof(float) * 4 * W * H), *img = malloc(sizeof(float) * 4 * W * H);
    if (!s || !ref || !img || lc_device_create(&(lc_device_desc){.target = LC_TARGET_SCALAR, .threads = 1}, &owner) ||
        scenes3_create(owner, s) != 0) {
        printf("FAIL setup: %s\n", lc_last_error());
        return 1;
    }
    if (hashes_only) { /* one line per target and scene: the child of the run below */
        for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++)
            for (int k = 0; k < 3 && usable((lc_target)t); k++)
                if (render((lc_target)t, 2, s, k, 32, img) == 0)
                    printf("%s %s %016llx\n", lc_target_name((lc_target)t), s->name[k],
                           (unsigned long long)fnv(img, sizeof(float) * 4 * W * H));
        scenes3_destroy(s);
        lc_device_destroy(owner);
        free(s), free(ref), free(img);
        return 0;
    }
    static const int threads[] = {1, 2, 4}, tiles[] = {8, 13, 32, 64};
    char expect[4096] = "";
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!usable((lc_target)t)) {
            printf("skip %s: %s\n", lc_target_name((lc_target)t),
                   lc_target_compiled((lc_target)t) ? "this CPU cannot run it" : "not compiled in");
            continue;
        }
        for (int k = 0; k < 3; k++) {
            const char *tn = lc_target_name((lc_target)t);
            if (render((lc_target)t, 2, s, k, 32, ref) != 0) {
                CHECK(0, "%s %s: render: %s", tn, s->name[k], lc_last_error());
                continue;
            }
            CHECK(scenes3_nontrivial(ref, W, H), "%s %s: the image shows the scene", tn, s->name[k]);
            snprintf(expect + strlen(expect), sizeof expect - strlen(expect), "%s %s %016llx\n", tn, s->name[k],
                     (unsigned long long)fnv(ref, sizeof(float) * 4 * W * H));
            int same = 0, runs = 0;
            char bad[160] = "";
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 4; b++)
                    for (int rep = 0; rep < 2; rep++) {
                        runs++;
                        if (render((lc_target)t, threads[a], s, k, tiles[b], img) == 0 &&
                            memcmp(img, ref, sizeof(float) * 4 * W * H) == 0)
                            same++;
                        else if (!bad[0])
                            snprintf(bad, sizeof bad, ": first difference at %d threads, tile %d, repeat %d",
                                     threads[a], tiles[b], rep);
                    }
            CHECK(same == runs, "%s %s: %d of %d renders (threads 1, 2, 4 x tiles 8, 13, 32, 64 x 2) byte-identical%s",
                  tn, s->name[k], same, runs, bad);
        }
    }
    /* a second process must print the same hashes */
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "'%s' --hashes", argv[0]);
    FILE *p = popen(cmd, "r");
    char got[4096] = "";
    size_t n = p ? fread(got, 1, sizeof got - 1, p) : 0;
    got[n] = '\0';
    int rc = p ? pclose(p) : -1;
    CHECK(rc == 0 && expect[0] && !strcmp(got, expect), "a second process renders the same bytes on every target%s%s",
          strcmp(got, expect) ? ":\n  want:\n" : "", strcmp(got, expect) ? expect : "");
    /* the identity check can fail: one voxel 1e-3 higher changes the bytes */
    s->grid[(12 * S3_G + 12) * S3_G + 12] += 1e-3f;
    lc_volume *g2 = NULL;
    lc_grid_desc gd = {.size = {S3_G, S3_G, S3_G}, .type = LC_VALUE_FLOAT32, .data = s->grid,
                       .spacing = {0.125f, 0.125f, 0.125f}, .origin = {-1.4f, -1.4f, -1.4f}};
    if (render(LC_TARGET_SCALAR, 1, s, 1, 32, ref) == 0 && lc_grid_create(owner, &gd, &g2) == LC_OK) {
        lc_volume *keep = s->vol[1];
        s->vol[1] = g2;
        CHECK(render(LC_TARGET_SCALAR, 1, s, 1, 32, img) == 0 && memcmp(img, ref, sizeof(float) * 4 * W * H) != 0,
              "control: one voxel 1e-3 higher changes the bytes (the comparison can fail)");
        s->vol[1] = keep;
    } else
        CHECK(0, "control render: %s", lc_last_error());
    lc_volume_destroy(g2);
    scenes3_destroy(s);
    lc_device_destroy(owner);
    free(s), free(ref), free(img);
    return check_summary("determinism");
}
