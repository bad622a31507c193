/* lanecast render PARTICLES (and lanecast demo): the particle flags,
 * defaults and stats (Knoll et al. 2014). See cli_kind.h. */
#include <math.h>
#include <string.h>
#include "args.h"
#include "cli_kind.h"
#include "cli_mpi.h"

static const char help[] =
    "particles (sums of truncated Gaussians, Knoll et al. 2014):\n"
    "  INPUT                 .xyz/.extxyz (element x y z, frames), .pdb/.ent (ATOM/HETATM, MODELs as\n"
    "                        frames), .cif (mmCIF _atom_site, models as frames), .gro (frames), .csv\n"
    "                        (named columns), optionally .gz; .dcd (CHARMM/NAMD trajectory, with\n"
    "                        --topology FILE.psf), .xtc/.trr (GROMACS trajectories, nm read as\n"
    "                        Angstrom, with --topology FILE.gro|.pdb|.psf; TRR: --value speed|force),\n"
    "                        LAMMPS text dumps, GADGET snapshots (format 1 or 2),\n"
    "                        HDF5 PartTypeN snapshots; raw float32 x,y,z triples with --raw-particles\n"
    "  --raw-particles N     INPUT holds exactly N little-endian float32 xyz triples (needs --radius)\n"
    "  --radius R            radius of every particle (default: covalent radius by element)\n"
    "  --radius-scale S      multiply element radii by S\n"
    "  --field-by MODE       field ids from an attribute: none (one field), element (one field per\n"
    "                        element), cpk (by element class: C, N, O, S, P, H, other, and solvent),\n"
    "                        type (atom type: mmCIF/GRO/PSF; LAMMPS: type T is field T-1;\n"
    "                        GADGET/HDF5: each particle type present, the default there), chain,\n"
    "                        residue (residue name), or column NAME, a named column's values:\n"
    "                          PDB   record serial name altloc resname chain resid icode x y z\n"
    "                                occupancy bfactor (tempfactor, beta) segid element charge\n"
    "                          mmCIF any _atom_site item (label_comp_id, auth_asym_id, ...) or the\n"
    "                                PDB names above (resname, chain, bfactor, ...)\n"
    "                          DCD   a PSF column: segid resid resname name type charge mass element\n"
    "                          LAMMPS, CSV  any column (numbers or words)\n"
    "                        Distinct values get fields 0..7 in order of first appearance; the 9th\n"
    "                        and later share field 7 (one warning). A format without the attribute\n"
    "                        or column fails naming it. --fields is the same flag\n"
    "  --select EXPR         read only the atoms EXPR selects: all, protein, backbone, water, ion,\n"
    "                        solvent, element C N O, name CA, resname ALA, chain A, segid PROA,\n"
    "                        type CT1, index 0:999, resid 10:20, joined by and, or, not and\n"
    "                        parentheses; words may end in * (prefix). Which keywords a format\n"
    "                        answers (others fail naming the keyword and the format):\n"
    "                          PDB, DCD+PSF  all; GRO, XYZ  those of their columns; mmCIF  all but\n"
    "                          segid and type; CSV  index and the columns it has (type or field,\n"
    "                          element, name, resname, chain, segid, resid); LAMMPS, GADGET, HDF5\n"
    "                          index and type (atom / particle type)\n"
    "  --value COLUMN        k_i (the Gaussian's weight) from a per-particle number:\n"
    "                          PDB   occupancy, bfactor (tempfactor, beta), charge ('2-' is -2), or\n"
    "                                another numeric column above (serial, resid, x, y, z)\n"
    "                          mmCIF any numeric _atom_site item (occupancy, B_iso_or_equiv alias\n"
    "                                bfactor, pdbx_formal_charge alias charge, ...)\n"
    "                          DCD   the PSF's mass, charge or resid\n"
    "                          CSV   any column (default: value, else mass); LAMMPS any per-atom\n"
    "                                column (c_pe, vx, q); GADGET/HDF5 none (default), mass, u,\n"
    "                                rho, hsml or any block: GADGET a block label (TEMP; format 1:\n"
    "                                the standard blocks), HDF5 a dataset of the PartTypeN groups\n"
    "                                (Temperature, ElementAbundance/Oxygen); NAME:K the component K\n"
    "                                of N x C values (Velocities:0), |NAME| their magnitude;\n"
    "                                lanecast info lists a snapshot's blocks\n"
    "                        a column the file lacks fails naming the file and the column; a cell\n"
    "                        that is not a number fails naming the line\n"
    "  --knn K               GADGET: radius = distance to the K-th nearest particle of the same type\n"
    "                        where there is no smoothing length (default 32)\n"
    "  --types LIST          GADGET: the particle types to read, e.g. 0,1 (default: all)\n"
    "  --drop-invalid        drop particles with bad data (counted) instead of failing\n"
    "  --leaf N              particles per BVH leaf, 1..32 (default 4)\n"
    "  --canonical-order 0|1 1 (the default): the BVH in a canonical order (Morton code of the\n"
    "                        centres), so each sample adds its terms in one order and mpirun's image is\n"
    "                        this one's bit for bit (docs/mpi.md); 0: Embree's SAH build\n"
    "  --method coherent|direct   coherent packets with sample buffers (default) or the per-sample\n"
    "                        gather through the BVH (the paper's baseline)\n"
    "  --kernel NAME         the radial kernel: gaussian (the default), or an SPH kernel with support\n"
    "                        radius H = the particle radius: m4 (cubic spline), m5, m6, wendland-c2,\n"
    "                        wendland-c4, wendland-c6\n"
    "  --sigma S             truncation radius in radii (default 2)\n"
    "  --kappa K             global density scale (default 1)\n"
    "  --spheres SCALE       also ray-trace opaque spheres of radius SCALE * r (paper §5.2)\n"
    "  --buffer K            coherent samples per ray per pass (default: adapted per ray group,\n"
    "                        up to 128, 128/M for M fields; the image does not depend on it)\n"
    "  --kernel NAME         the radial kernel: gaussian (default), or an SPH kernel m4 (cubic\n"
    "                        spline), m5, m6, wendland-c2, wendland-c4, wendland-c6 with support\n"
    "                        radius H = the particle's radius (GADGET's HSML; no --sigma), normalised\n"
    "                        in 3-D; with --value A on a GADGET/HDF5 snapshot the field is the SPH\n"
    "                        interpolant sum m/rho A W (m and rho from the file; gas only)\n"
    "  --hsml-is h|H         GADGET/HDF5: the file's smoothing lengths are h (H = gamma h, gamma the\n"
    "                        kernel's) or H (default: GADGET HSML and AREPO SmoothingLength are H,\n"
    "                        SWIFT SmoothingLengths are h); lanecast info says which was applied\n"
    "  --normalise           GADGET/HDF5 with an SPH kernel and --value A: the normalised SPH\n"
    "                        interpolant sum m/rho A W / sum m/rho W (0 where no particle reaches;\n"
    "                        dvr/mip/iso render with --method direct)\n"
    "  defaults: method coherent, dt a quarter of the smallest radius (SPH kernels: an eighth),\n"
    "  range 0..kappa (SPH kernels: 0..the largest peak kappa k norm / H^3); molecules\n"
    "  (PDB, mmCIF, GRO, XYZ, DCD) with no --fields, --tf, --colormap or --opacity: --fields cpk\n"
    "  coloured by element (C grey, N blue, O red, S yellow, P orange, H white, others green) with\n"
    "  water and ions (by residue name) a faint blue haze; otherwise TF heat (demo for several\n"
    "  fields) with a peak extinction of 1 / the largest radius\n"
    "  examples: lanecast render 1tii.pdb -o 1tii.png --shade --fields element --tf demo\n"
    "            lanecast render 1tw7_solvated.pdb --select 'protein and not element H' -o prot.png\n"
    "            lanecast render 1tw7_solvated.pdb --select 'water and index 0:2999' --colormap magma -o w.png\n"
    "            lanecast render atoms.f32 --raw-particles 1000000 --radius 0.5 -o big.exr --stats\n"
    "            lanecast render melt.lammpstrj --fields type --frame 10 -o melt.png\n"
    "            lanecast render gadget_lcdm_gas.dat --types 0 --value u --knn 16 -o gas.png\n"
    "            lanecast render 1tii.pdb --value bfactor --field-by column chain -o bfac.png\n"
    "            lanecast render adk.dcd --topology adk.psf --value charge --field-by column segid -o q.png\n"
    "            lanecast render md.xtc --topology conf.gro --frame 500 --select protein -o md.png\n"
    "            lanecast render atoms.csv --select 'type 1 2 and index 0:9999' --value energy -o e.png\n"
    "\n";

static lc_particle_params params;
static int fields_given, cpk;

static int parse_flag(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first)
{
    const char *a = argv[*i], *v;
    static const char *const flags[] = {"--raw-particles", "--radius", "--radius-scale", "--fields", "--drop-invalid",
                                        "--leaf",          "--sigma",  "--kappa",        "--spheres", "--buffer",
                                        "--value",         "--knn",    "--types",        "--select",  "--field-by",
                                        "--kernel",        "--hsml-is",  "--normalise",    "--canonical-order"};
    int known = 0;
    for (size_t k = 0; k < sizeof flags / sizeof flags[0]; k++) known |= !strcmp(a, flags[k]);
    if (!known) return 0;
    if (!*first) *first = a;
    if (!strcmp(a, "--drop-invalid")) return cli_load_add(load, cmd, "drop_invalid", "1") ? -1 : 1;
    if (!strcmp(a, "--normalise")) /* the kernels divide (params), the loader emits m / rho (load option) */
        return params.normalise = 1, cli_load_add(load, cmd, "normalise", "1") ? -1 : 1;
    if (!(v = arg_value(cmd, argc, argv, i))) return -1;
    float f;
    int n;
    size_t z;
    if (!strcmp(a, "--raw-particles")) {
        if (arg_size_t(cmd, a, v, &z)) return -1;
        load->format = "raw-particles";
        return cli_load_add(load, cmd, "count", v) ? -1 : 1;
    }
    if (!strcmp(a, "--radius") || !strcmp(a, "--radius-scale")) {
        if (arg_float(cmd, a, v, 1e-30f, 1e30f, &f)) return -1;
        return cli_load_add(load, cmd, a[8] ? "radius_scale" : "radius", v) ? -1 : 1;
    }
    if (!strcmp(a, "--fields") || !strcmp(a, "--field-by")) { /* --fields: the older name */
        static const char *const modes[] = {"none", "element", "cpk", "type", "chain", "residue"};
        int ok = 0;
        for (size_t k = 0; k < sizeof modes / sizeof modes[0]; k++) ok |= !strcmp(v, modes[k]);
        char col[1024];
        if (!strcmp(v, "column")) { /* column NAME */
            const char *name = arg_value(cmd, argc, argv, i);
            if (!name) return -1;
            snprintf(col, sizeof col, "column:%s", name);
            v = col, ok = 1;
        } else if (!strncmp(v, "column:", 7) && v[7])
            ok = 1;
        if (!ok) {
            fprintf(stderr, "%s: %s: '%s' is not none, element, cpk, type, chain, residue or column NAME\n", cmd, a, v);
            return -1;
        }
        fields_given = 1;
        cpk = !strcmp(v, "cpk");
        return cli_load_add(load, cmd, "fields", v) ? -1 : 1;
    }
    if (!strcmp(a, "--select")) {
        if (lc_select_check(v) != LC_OK) {
            fprintf(stderr, "%s: --select: %s\n", cmd, lc_last_error());
            return -1;
        }
        return cli_load_add(load, cmd, "select", v) ? -1 : 1;
    }
    if (!strcmp(a, "--value")) return cli_load_add(load, cmd, "value", v) ? -1 : 1;
    if (!strcmp(a, "--kernel")) { /* the render kernel, and the loaders' h -> H and SPH weights (load option kernel) */
        if (lc_kernel_from_name(v, &params.kernel) != LC_OK) {
            fprintf(stderr, "%s: --kernel: '%s' is not gaussian, m4, m5, m6, wendland-c2, wendland-c4 or wendland-c6\n",
                    cmd, v);
            return -1;
        }
        return cli_load_add(load, cmd, "kernel", v) ? -1 : 1;
    }
    if (!strcmp(a, "--hsml-is")) {
        if (strcmp(v, "h") && strcmp(v, "H")) {
            fprintf(stderr, "%s: --hsml-is: '%s' is not h (the code's smoothing length) or H (the support radius)\n",
                    cmd, v);
            return -1;
        }
        return cli_load_add(load, cmd, "hsml_is", v) ? -1 : 1;
    }
    if (!strcmp(a, "--types")) return cli_load_add(load, cmd, "types", v) ? -1 : 1;
    if (!strcmp(a, "--knn")) return arg_int(cmd, a, v, 1, 1024, &n) || cli_load_add(load, cmd, "knn", v) ? -1 : 1;
    if (!strcmp(a, "--canonical-order"))
        return arg_int(cmd, a, v, 0, 1, &n) || cli_load_add(load, cmd, "canonical_order", v) ? -1 : 1;
    if (!strcmp(a, "--leaf")) return arg_int(cmd, a, v, 1, 32, &n) || cli_load_add(load, cmd, "leaf_size", v) ? -1 : 1;
    if (!strcmp(a, "--sigma")) { /* under mpirun also a load option: the ghosts reach sigma radii */
        if (arg_float(cmd, a, v, 1e-3f, 100.0f, &params.sigma)) return -1;
        return cli_mpi_launched() && cli_load_add(load, cmd, "sigma", v) ? -1 : 1;
    }
    if (!strcmp(a, "--spheres")) return arg_float(cmd, a, v, 1e-3f, 100.0f, &params.sphere_scale) ? -1 : 1;
    if (!strcmp(a, "--buffer")) return arg_int(cmd, a, v, 1, 4096, &params.buffer_samples) ? -1 : 1;
    /* --kappa */
    if (arg_float(cmd, a, v, -1e30f, 1e30f, &params.kappa)) return -1;
    if (params.kappa == 0.0f) {
        fprintf(stderr, "%s: --kappa: 0 would make every value zero\n", cmd);
        return -1;
    }
    return 1;
}

static lc_status apply(lc_volume *v, lc_render_desc *rd)
{
    (void)rd;
    return lc_particles_set_params(v, &params);
}

/* Molecules (the formats of elements and residues: PDB, mmCIF, GRO, XYZ,
 * DCD) are coloured by element class unless the user chose fields or a
 * classification. The format is the one whose option list format_options
 * is (decide_kind hands over lc_format_info.options). */
static int defaults(const char *cmd, cli_load *load, const char *format_options, int tf_given)
{
    static const char *const molecular[] = {"pdb", "mmcif", "gro", "xyz", "dcd"};
    int mol = 0;
    lc_format_info f;
    for (int i = 0; format_options && lc_format_get(i, &f) == LC_OK; i++)
        if (f.options == format_options)
            for (size_t k = 0; k < sizeof molecular / sizeof molecular[0]; k++) mol |= !strcmp(f.name, molecular[k]);
    if (fields_given || tf_given || !mol) return 0;
    cpk = 1;
    return cli_load_add(load, cmd, "fields", "cpk");
}

/* fields = cpk: 0 C, 1 N, 2 O, 3 S, 4 P, 5 H, 6 other, 7 solvent */
static lc_status cpk_tf(lc_device *dev, int nfields, float t, lc_tf **out)
{
    static const float rgb[8][3] = {{0.6f, 0.6f, 0.6f}, {0.25f, 0.4f, 1.0f}, {1.0f, 0.15f, 0.1f}, {1.0f, 0.85f, 0.2f},
                                    {1.0f, 0.55f, 0.0f}, {0.95f, 0.95f, 0.95f}, {0.3f, 0.85f, 0.35f},
                                    {0.45f, 0.65f, 1.0f}};
    float col[8][8], op[8][6];
    lc_tf_field f[8];
    memset(f, 0, sizeof f);
    for (int i = 0; i < nfields && i < 8; i++) {
        for (int k = 0; k < 2; k++) col[i][4 * k] = (float)k, memcpy(&col[i][4 * k + 1], rgb[i], sizeof rgb[i]);
        /* the preset ramp; solvent a faint haze */
        float peak = i == 7 ? 0.03f * t : t;
        float o[6] = {0.0f, 0.0f, 0.1f, 0.0f, 1.0f, peak};
        memcpy(op[i], o, sizeof o);
        f[i].color = col[i], f[i].ncolor = 2, f[i].opacity = op[i], f[i].nopacity = 3;
    }
    return lc_tf_create(dev, f, nfields, out);
}

static lc_status default_tf(lc_device *dev, const lc_volume *v, const cli_tf_req *req, lc_tf **out)
{
    lc_particles_info pi;
    lc_status s = lc_particles_get_info(v, &pi);
    if (s != LC_OK) return s;
    float t = req->tau > 0.0f ? req->tau : (pi.max_radius > 0.0f ? 1.0f / pi.max_radius : 1.0f);
    if (cpk && !req->preset && !req->colormap) return cpk_tf(dev, pi.nfields, t, out);
    const char *name = req->preset ? req->preset : req->colormap ? req->colormap : pi.nfields > 1 ? "demo" : "heat";
    return lc_tf_preset(dev, name, pi.nfields, t, out);
}

static void print_stats(const lc_volume *v, double load_seconds, FILE *f)
{
    lc_particles_info pi;
    if (lc_particles_get_info(v, &pi) != LC_OK) return;
    fprintf(f, "particles     %zu (%zu dropped), %d fields, radius %.4g..%.4g\n", pi.count, pi.dropped, pi.nfields,
            (double)pi.min_radius, (double)pi.max_radius);
    fprintf(f, "kernel        %s%s%s\n", lc_kernel_name(pi.params.kernel),
            pi.params.kernel == LC_KERNEL_GAUSSIAN ? " (radius = standard deviation, cut at sigma radii)"
                                                   : " (radius = support radius H)",
            pi.params.normalise ? "; normalised: sum m/rho A W / sum m/rho W" : "");
    if (pi.radius_note[0]) fprintf(f, "radii         %s\n", pi.radius_note);
    fprintf(f, "load          %.3f s (reading and BVH build)\n", load_seconds);
    fprintf(f, "bvh           %d nodes, depth %d, %.2f MB, build %.3f s; particle data %.2f MB\n", pi.bvh_nodes,
            pi.bvh_depth, (double)pi.bvh_bytes / 1e6, pi.build_seconds, (double)pi.data_bytes / 1e6);
}

const cli_kind cli_particles = {LC_KIND_PARTICLES, help, parse_flag, apply, defaults, default_tf, print_stats,
                                 "gaussians    "};

/* The procedural demo: a double helix of "atoms" (field 0) inside a shell of
 * a second species (field 1), fixed seed, with its own TF. */
lc_status cli_demo_scene(lc_device *dev, lc_volume **out, lc_tf **tf)
{
    enum { NHELIX = 4000, NSHELL = 6000 };
    static float xyz[3 * (NHELIX + NSHELL)], r[NHELIX + NSHELL];
    static uint8_t field[NHELIX + NSHELL];
    uint32_t seed = 12345u;
#define RND() ((seed = seed * 1664525u + 1013904223u), (float)(seed >> 8) / 16777216.0f)
    for (int i = 0; i < NHELIX; i++) {
        float s = (float)(i / 2) / (NHELIX / 2), ang = s * 6.0f * 6.2831853f + (i & 1) * 3.14159265f;
        xyz[3 * i] = 6.0f * cosf(ang) + 0.6f * (RND() - 0.5f);
        xyz[3 * i + 1] = -20.0f + 40.0f * s;
        xyz[3 * i + 2] = 6.0f * sinf(ang) + 0.6f * (RND() - 0.5f);
        r[i] = 0.7f;
        field[i] = 0;
    }
    for (int i = NHELIX; i < NHELIX + NSHELL; i++) {
        float u = 2.0f * RND() - 1.0f, ph = 6.2831853f * RND(), rad = 14.0f + 2.0f * RND();
        float sx = sqrtf(1.0f - u * u);
        xyz[3 * i] = rad * sx * cosf(ph);
        xyz[3 * i + 1] = 1.6f * rad * u;
        xyz[3 * i + 2] = rad * sx * sinf(ph);
        r[i] = 0.5f + 0.5f * RND();
        field[i] = 1;
    }
#undef RND
    lc_particles_desc d = {.count = NHELIX + NSHELL, .positions = xyz, .radii = r, .fields = field, .nfields = 2};
    lc_status s = lc_particles_create(dev, &d, out);
    if (s != LC_OK || !tf) return s;
    /* the helix warm and dense, the shell a faint cool haze */
    static const float warm[] = {0.0f, 0.7f, 0.15f, 0.05f, 0.5f, 1.0f, 0.55f, 0.1f, 1.0f, 1.0f, 0.95f, 0.7f};
    static const float cool[] = {0.0f, 0.1f, 0.3f, 0.8f, 1.0f, 0.5f, 0.85f, 1.0f};
    static const float op0[] = {0.0f, 0.0f, 0.15f, 0.0f, 0.6f, 3.0f, 1.0f, 6.0f};
    static const float op1[] = {0.0f, 0.0f, 0.2f, 0.0f, 1.0f, 0.18f};
    lc_tf_field f[2] = {{warm, 4 - 1, op0, 4, 1, {0.0f, 1.0f}}, {cool, 2, op1, 3, 1, {0.0f, 1.0f}}};
    return lc_tf_create(dev, f, 2, tf);
}
