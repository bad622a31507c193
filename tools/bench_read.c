/* lanecast bench --read FILE: trajectory reading rates (docs/bench/traj.md)
 * through the format's registry entry, descriptor only (no volume, no BVH;
 * host/formats/format.h: the benchmark looks inside the library here, as the
 * public API always builds the volume): the frames counted from their
 * headers, every frame read in order (each read finds its frame from the
 * headers, since no index is kept between loads, so this grows with
 * frames^2), the middle frame read alone (random access) and frame 0 read
 * 200 times (decoding alone). The best of `rounds` passes each; one "read"
 * record. */
#include <string.h>
#include "bench_run.h"
#include "host/formats/format.h"

static const lci_format *const traj_formats[] = {&lci_format_xtc, &lci_format_trr, &lci_format_dcd};

static const lci_format *format_of(const char *path)
{
    const char *dot = strrchr(path, '.');
    for (size_t i = 0; dot && i < sizeof traj_formats / sizeof traj_formats[0]; i++)
        if (!strcmp(dot + 1, traj_formats[i]->name)) return traj_formats[i];
    return NULL;
}

/* the topology is the readers' own default: the .psf, .gro or .pdb of the same name */
static int read_frame(lc_device *dev, const lci_format *f, const char *path, int64_t k, size_t *natoms)
{
    lc_option r = {"radius", "1"};
    lc_load_desc d = {.frame = k, .options = &r, .noptions = 1};
    lci_read_args a = {path, &d, &r, 1, f->name};
    lci_loaded l = {0};
    if (f->read(dev, &a, &l) != LC_OK) return -1;
    *natoms = ((const lc_particles_desc *)l.desc)->count;
    lci_loaded_free(&l);
    return 0;
}

int bench_read(const char *path, int rounds, FILE *out)
{
    const lci_format *f = format_of(path);
    if (!f || !f->frames) {
        fprintf(stderr, "lanecast bench: --read %s: not a trajectory lanecast bench times (.xtc, .trr, .dcd)\n", path);
        return 2;
    }
    lc_device *dev;
    if (lc_device_create(&(lc_device_desc){.threads = 1}, &dev) != LC_OK) return 1;
    int64_t frames = 0;
    double t0 = bench_now();
    int ok = f->frames(dev, path, &frames) == LC_OK && frames > 0;
    double tcount = bench_now() - t0, all = 1e30, mid = 1e30, first = 1e30;
    size_t natoms = 0;
    for (int r = 0; ok && r < rounds; r++) {
        t0 = bench_now();
        for (int64_t k = 0; ok && k < frames; k++) ok = !read_frame(dev, f, path, k, &natoms);
        double t = bench_now() - t0;
        all = t < all ? t : all;
        t0 = bench_now();
        ok = ok && !read_frame(dev, f, path, frames / 2, &natoms);
        t = bench_now() - t0;
        mid = t < mid ? t : mid;
        t0 = bench_now();
        for (int i = 0; ok && i < 200; i++) ok = !read_frame(dev, f, path, 0, &natoms);
        t = (bench_now() - t0) / 200;
        first = t < first ? t : first;
    }
    if (!ok) {
        fprintf(stderr, "lanecast bench: --read %s: %s\n", path, frames > 0 ? lc_last_error() : "no frames");
        lc_device_destroy(dev);
        return 1;
    }
    fprintf(out, "{\"record\": \"read\", \"file\": ");
    bench_json_str(out, path);
    fprintf(out, ", \"format\": \"%s\", \"frames\": %lld, \"atoms\": %zu, \"rounds\": %d, \"count_s\": %.6g, "
                 "\"all_s\": %.6g, \"frames_per_s\": %.6g, \"atoms_per_s\": %.6g, \"middle_frame\": %lld, "
                 "\"middle_s\": %.6g, \"frame0_s\": %.6g, \"frame0_atoms_per_s\": %.6g, \"loadavg\": %.2f, %s}\n",
            f->name, (long long)frames, natoms, rounds, tcount, all, (double)frames / all,
            (double)frames * (double)natoms / all, (long long)(frames / 2), mid, first, (double)natoms / first,
            bench_loadavg(), bench_machine_json());
    fflush(out);
    lc_device_destroy(dev);
    return 0;
}
