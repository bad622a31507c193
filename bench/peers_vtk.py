#!/usr/bin/python3
"""lanecast against VTK 9's vtkFixedPointVolumeRayCastMapper on the same
structured volume, transfer function, camera, sample distance and image size
(run by bench/peers.sh under xvfb-run; it installs python3-vtk9 when asked).

usage: peers_vtk.py LANECAST DATA_DIR OUT_DIR RECORDS.jsonl [name ...]
  (default engine neghip 1tii: .nhdr volumes under DATA_DIR/volumes, .pdb files under DATA_DIR/particles)

Particles (a .pdb): VTK's proxy path, interpolation onto a grid with a
Gaussian kernel and ray casting of the grid (particles() below).
Per volume (an .nhdr under DATA_DIR/volumes): the TF is written as SPEC.md
JSON for lanecast (colour points, tau per world unit over the value range)
and given to VTK as a colour TF and a scalar opacity at unit distance 1,
alpha = 1 - exp(-tau) (so both see alpha = 1 - exp(-tau dt) per sample),
linear interpolation, no shading, black background, perspective camera
from lanecast's default view direction (azimuth 35, elevation 25, +y up, fovy
40) at the distance where the bounding sphere fills the view. Times: time to
first image (reading the file, building, first frame: lanecast's process wall
time, VTK's from reading the raw data) and the median of 5 further frames,
both with 2 threads. Writes one "peer" record per volume and a composite PNG
(lanecast | VTK | |difference| x 4) into OUT_DIR.
"""
import gzip
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

SIZE = 512
THREADS = 2
VIRIDIS = [[0.0, 0.267, 0.005, 0.329], [0.25, 0.229, 0.322, 0.546], [0.5, 0.128, 0.567, 0.551],
           [0.75, 0.369, 0.789, 0.383], [1.0, 0.993, 0.906, 0.144]]


def read_nhdr(path):
    hdr = {}
    for line in open(path):
        if ":" in line and not line.startswith("#"):
            k, v = line.split(":", 1)
            hdr[k.strip()] = v.strip()
    sizes = [int(x) for x in hdr["sizes"].split()]
    spacing = [float(x) for x in hdr.get("spacings", "1 1 1").split()]
    types = {"uchar": np.uint8, "unsigned char": np.uint8, "uint8": np.uint8, "ushort": np.uint16,
             "unsigned short": np.uint16, "uint16": np.uint16, "short": np.int16, "float": np.float32}
    dtype = np.dtype(types[hdr["type"]]).newbyteorder("<")
    data_path = os.path.join(os.path.dirname(path), hdr["data file"])
    raw = gzip.open(data_path).read() if hdr.get("encoding") == "gzip" else open(data_path, "rb").read()
    arr = np.frombuffer(raw, dtype=dtype, count=sizes[0] * sizes[1] * sizes[2])
    return sizes, spacing, arr


def camera(sizes, spacing):
    hi = [(n - 1) * s for n, s in zip(sizes, spacing)]
    at = [h / 2 for h in hi]
    radius = 0.5 * math.sqrt(sum(h * h for h in hi))
    dist = radius / math.sin(math.radians(20.0))
    az, el = math.radians(35.0), math.radians(25.0)
    d = [math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)]
    return [a + dist * x for a, x in zip(at, d)], at


def composite(a, b, path, title):
    diff = np.clip(4 * np.abs(a - b), 0, 1)
    fig, axs = plt.subplots(1, 3, figsize=(12, 4.4))
    for ax, img, name in zip(axs, [a, b, diff], ["lanecast", "VTK FixedPointVolumeRayCast", "|difference| x 4"]):
        ax.imshow(img)
        ax.set_title(name, fontsize=9)
        ax.axis("off")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def run_lanecast(exe, path, tf_path, eye, at, dt, out_png, extra=()):
    args = [exe, "render", path, "-o", out_png, "--size", "%dx%d" % (SIZE, SIZE), "--tf", tf_path,
            "--eye", ",".join("%.6g" % x for x in eye), "--at", ",".join("%.6g" % x for x in at), "--fov", "40",
            "--dt", "%.6g" % dt, "--threads", str(THREADS), "--stats", "--quiet"] + list(extra)
    walls, renders = [], []
    for _ in range(6):
        t0 = time.perf_counter()
        p = subprocess.run(args, capture_output=True, text=True)
        walls.append(time.perf_counter() - t0)
        if p.returncode:
            raise RuntimeError("lanecast render failed: " + p.stderr.strip())
        m = re.search(r"^render\s+([0-9.]+) s", p.stdout + p.stderr, re.M)
        renders.append(float(m.group(1)) if m else float("nan"))
    return walls[0], statistics.median(renders[1:]), " ".join(args)


def nhdr_image(path):
    sizes, spacing, arr = read_nhdr(path)
    img = vtk.vtkImageData()
    img.SetDimensions(*sizes)
    img.SetSpacing(*spacing)
    img.GetPointData().SetScalars(numpy_support.numpy_to_vtk(np.ascontiguousarray(arr), deep=1))
    return img


def read_pdb(path):
    xyz = [[float(l[30:38]), float(l[38:46]), float(l[46:54])] for l in open(path)
           if l.startswith("ATOM") or l.startswith("HETATM")]
    return np.array(xyz)


def particle_image(xyz, radius, lo, spacing, dims):
    """VTK's proxy path for particles: vtkPointInterpolator with a Gaussian kernel of radius 2r and
    sharpness sqrt(2), weights not normalised, every point's scalar 1: the grid holds the sum of
    truncated Gaussians exp(-d^2 / 2r^2) over d < 2r, lanecast's particle field with sigma 2."""
    pts = vtk.vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(xyz, dtype=np.float32), deep=1))
    poly = vtk.vtkPolyData()
    poly.SetPoints(pts)
    ones = numpy_support.numpy_to_vtk(np.ones(len(xyz), dtype=np.float32), deep=1)
    ones.SetName("one")
    poly.GetPointData().SetScalars(ones)
    grid = vtk.vtkImageData()
    grid.SetDimensions(*dims)
    grid.SetOrigin(*lo)
    grid.SetSpacing(spacing, spacing, spacing)
    kern = vtk.vtkGaussianKernel()
    kern.SetRadius(2 * radius)
    kern.SetSharpness(math.sqrt(2))  # VTK: exp(-(sharpness d / R)^2) = exp(-d^2 / 2r^2) with R = 2r
    kern.NormalizeWeightsOff()
    loc = vtk.vtkStaticPointLocator()
    loc.SetDataSet(poly)
    interp = vtk.vtkPointInterpolator()
    interp.SetInputData(grid)
    interp.SetSourceData(poly)
    interp.SetKernel(kern)
    interp.SetLocator(loc)
    interp.Update()
    out = interp.GetOutput()
    out.GetPointData().SetActiveScalars("one")
    return out


def run_vtk(make_image, lo, hi, tf_color, tf_opacity, eye, at, dt, out_png):
    vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(THREADS)
    t0 = time.perf_counter()
    img = make_image()
    ctf, otf = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    for v, r, g, b in tf_color:
        ctf.AddRGBPoint(lo + v * (hi - lo), r, g, b)
    for v, tau in tf_opacity:
        otf.AddPoint(lo + v * (hi - lo), 1.0 - math.exp(-tau))  # alpha at unit distance 1
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(ctf)
    prop.SetScalarOpacity(otf)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    mapper = vtk.vtkFixedPointVolumeRayCastMapper()
    mapper.SetInputData(img)
    mapper.SetAutoAdjustSampleDistances(0)
    mapper.SetSampleDistance(dt)
    mapper.SetImageSampleDistance(1.0)
    vol = vtk.vtkVolume()
    vol.SetMapper(mapper)
    vol.SetProperty(prop)
    ren = vtk.vtkRenderer()
    ren.SetBackground(0, 0, 0)
    ren.AddVolume(vol)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(SIZE, SIZE)
    win.AddRenderer(ren)
    cam = ren.GetActiveCamera()
    cam.SetPosition(*eye)
    cam.SetFocalPoint(*at)
    cam.SetViewUp(0, 1, 0)
    cam.SetViewAngle(40)
    ren.ResetCameraClippingRange()
    win.Render()
    first = time.perf_counter() - t0
    frames = []
    for _ in range(5):
        cam.Modified()
        mapper.Modified()
        t1 = time.perf_counter()
        win.Render()
        frames.append(time.perf_counter() - t1)
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    w = vtk.vtkPNGWriter()
    w.SetFileName(out_png)
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()
    return first, statistics.median(frames), vtk.vtkVersion.GetVTKVersion()


def finish(name, kind, lc_png, vtk_png, lc_first, lc_frame, lc_cmd, vtk_first, vtk_frame, vtk_ver, extra, out_dir,
           records, title, mapper):
    a = plt.imread(lc_png)[..., :3]
    b = plt.imread(vtk_png)[..., :3]
    mse = float(np.mean((a - b) ** 2))
    psnr = 10 * math.log10(1 / mse) if mse > 0 else None
    comp = os.path.join(out_dir, "peer_vtk_%s.png" % name)
    composite(a, b, comp, title + ": lanecast %.3f s/frame, VTK %.3f s/frame" % (lc_frame, vtk_frame))
    rec = {"record": "peer", "peer": "vtk", "peer_version": vtk_ver, "peer_mapper": mapper, "scene": name,
           "kind": kind, "size": SIZE, "threads": THREADS, "lanecast_first_s": lc_first, "lanecast_frame_s": lc_frame,
           "peer_first_s": vtk_first, "peer_frame_s": vtk_frame, "frame_ratio_peer_over_lanecast": vtk_frame / lc_frame,
           "psnr_db_between": psnr, "max_diff_255_between": float(np.max(np.abs(a - b))) * 255,
           "composite": os.path.basename(comp), "lanecast_command": lc_cmd, "loadavg": os.getloadavg()[0]}
    rec.update(extra)
    with open(records, "a") as f:
        f.write(json.dumps(rec) + "\n")
    print("peers_vtk.py: %s lanecast %.4f s/frame (first %.3f s), VTK %.4f s/frame (first %.3f s), PSNR between %s dB "
          "-> %s" % (name, lc_frame, lc_first, vtk_frame, vtk_first, "%.1f" % psnr if psnr else "inf", comp))


def particles(exe, path, name, out_dir, records, radius=1.0):
    """The proxy path VTK users take for particles: interpolate onto a grid (spacing r/2) with a
    Gaussian kernel, then ray cast the grid; lanecast renders the particles themselves, all with
    radius r (--radius), sigma 2, kappa 1."""
    xyz = read_pdb(path)
    lo = xyz.min(axis=0) - 2 * radius
    hi = xyz.max(axis=0) + 2 * radius
    spacing = radius / 2
    dims = [int(math.ceil((h - l) / spacing)) + 1 for l, h in zip(lo, hi)]
    ext = [(n - 1) * spacing for n in dims]
    at = [l + e / 2 for l, e in zip(lo, ext)]
    rad = 0.5 * math.sqrt(sum(e * e for e in ext))
    dist = rad / math.sin(math.radians(20.0))
    az, el = math.radians(35.0), math.radians(25.0)
    eye = [a + dist * x for a, x in zip(at, [math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])]
    vmax, tau = 2.0, 1.0 / radius
    opacity = [[0.0, 0.0], [0.1, 0.0], [1.0, tau]]
    tf_path = os.path.join(out_dir, "peer_%s_tf.json" % name)
    with open(tf_path, "w") as f:
        json.dump({"range": [0.0, vmax], "color": VIRIDIS, "opacity": opacity}, f)
    dt = 0.25 * radius
    lc_png, vtk_png = (os.path.join("/tmp", "peer_%s_%s.png" % (name, k)) for k in ("lanecast", "vtk"))
    lc_first, lc_frame, lc_cmd = run_lanecast(exe, path, tf_path, eye, at, dt, lc_png, ["--radius", "%g" % radius])
    vtk_first, vtk_frame, vtk_ver = run_vtk(lambda: particle_image(read_pdb(path), radius, lo, spacing, dims), 0.0,
                                            vmax, VIRIDIS, opacity, eye, at, dt, vtk_png)
    finish(name, "particles", lc_png, vtk_png, lc_first, lc_frame, lc_cmd, vtk_first, vtk_frame, vtk_ver,
           {"count": len(xyz), "radius": radius, "dt": dt, "proxy_grid": dims}, out_dir, records,
           "%s, %d atoms, r %g, VTK: Gaussian interpolation onto %dx%dx%d, then ray casting" % (name, len(xyz), radius,
                                                                                                 *dims),
           "vtkPointInterpolator (Gaussian) + vtkFixedPointVolumeRayCastMapper")


def main():
    exe, data, out_dir, records = sys.argv[1:5]
    names = sys.argv[5:] or ["engine", "neghip", "1tii"]
    os.makedirs(out_dir, exist_ok=True)
    for name in names:
        if os.path.exists(os.path.join(data, "particles", name + ".pdb")):
            particles(exe, os.path.join(data, "particles", name + ".pdb"), name, out_dir, records)
            continue
        path = os.path.join(data, "volumes", name + ".nhdr")
        if not os.path.exists(path):
            print("peers_vtk.py: %s absent, skipped" % path)
            continue
        sizes, spacing, arr = read_nhdr(path)
        lo, hi = float(arr.min()), float(arr.max())
        diag = math.sqrt(sum(((n - 1) * s) ** 2 for n, s in zip(sizes, spacing)))
        tau = 16.0 / diag
        opacity = [[0.0, 0.0], [0.3, 0.0], [1.0, tau]]
        tf_path = os.path.join(out_dir, "peer_%s_tf.json" % name)
        with open(tf_path, "w") as f:
            json.dump({"range": [lo, hi], "color": VIRIDIS, "opacity": opacity}, f)
        eye, at = camera(sizes, spacing)
        dt = 0.5 * min(spacing)
        lc_png, vtk_png = (os.path.join("/tmp", "peer_%s_%s.png" % (name, k)) for k in ("lanecast", "vtk"))
        lc_first, lc_frame, lc_cmd = run_lanecast(exe, path, tf_path, eye, at, dt, lc_png)
        vtk_first, vtk_frame, vtk_ver = run_vtk(lambda: nhdr_image(path), lo, hi, VIRIDIS, opacity, eye, at, dt,
                                                vtk_png)
        finish(name, "grid", lc_png, vtk_png, lc_first, lc_frame, lc_cmd, vtk_first, vtk_frame, vtk_ver,
               {"dt": dt, "range": [lo, hi], "tau_max": tau}, out_dir, records,
               "%s %dx%dx%d, %dx%d, dt %.3g, 2 threads" % (name, *sizes, SIZE, SIZE, dt),
               "vtkFixedPointVolumeRayCastMapper")


if __name__ == "__main__":
    main()
