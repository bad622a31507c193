#!/usr/bin/python3
"""lanecast against VTK 9's vtkFixedPointVolumeRayCastMapper on the same
structured volume, transfer function, camera, sample distance and image size
(run by bench/peers.sh under xvfb-run; it installs python3-vtk9 when asked).

usage: peers_vtk.py LANECAST DATA_DIR OUT_DIR RECORDS.jsonl [volume ...]

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


def run_lanecast(exe, path, tf_path, eye, at, dt, out_png):
    args = [exe, "render", path, "-o", out_png, "--size", "%dx%d" % (SIZE, SIZE), "--tf", tf_path,
            "--eye", ",".join("%.6g" % x for x in eye), "--at", ",".join("%.6g" % x for x in at), "--fov", "40",
            "--dt", "%.6g" % dt, "--threads", str(THREADS), "--stats", "--quiet"]
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


def run_vtk(path, lo, hi, tf_color, tf_opacity, eye, at, dt, out_png):
    vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(THREADS)
    t0 = time.perf_counter()
    sizes, spacing, arr = read_nhdr(path)
    img = vtk.vtkImageData()
    img.SetDimensions(*sizes)
    img.SetSpacing(*spacing)
    img.GetPointData().SetScalars(numpy_support.numpy_to_vtk(np.ascontiguousarray(arr), deep=1))
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


def main():
    exe, data, out_dir, records = sys.argv[1:5]
    names = sys.argv[5:] or ["engine", "neghip"]
    os.makedirs(out_dir, exist_ok=True)
    for name in names:
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
        vtk_first, vtk_frame, vtk_ver = run_vtk(path, lo, hi, VIRIDIS, opacity, eye, at, dt, vtk_png)
        a = plt.imread(lc_png)[..., :3]
        b = plt.imread(vtk_png)[..., :3]
        mse = float(np.mean((a - b) ** 2))
        psnr = 10 * math.log10(1 / mse) if mse > 0 else float("inf")
        comp = os.path.join(out_dir, "peer_vtk_%s.png" % name)
        composite(a, b, comp, "%s %dx%dx%d, %dx%d, dt %.3g, 2 threads: lanecast %.3f s/frame, VTK %.3f s/frame"
                  % (name, *sizes, SIZE, SIZE, dt, lc_frame, vtk_frame))
        rec = {"record": "peer", "peer": "vtk", "peer_version": vtk_ver,
               "peer_mapper": "vtkFixedPointVolumeRayCastMapper", "scene": name, "size": SIZE, "threads": THREADS,
               "dt": dt, "range": [lo, hi], "tau_max": tau, "lanecast_first_s": lc_first,
               "lanecast_frame_s": lc_frame, "peer_first_s": vtk_first, "peer_frame_s": vtk_frame,
               "frame_ratio_peer_over_lanecast": vtk_frame / lc_frame, "psnr_db_between": psnr,
               "max_diff_255_between": float(np.max(np.abs(a - b))) * 255, "composite": os.path.basename(comp),
               "lanecast_command": lc_cmd, "loadavg": os.getloadavg()[0]}
        with open(records, "a") as f:
            f.write(json.dumps(rec) + "\n")
        print("peers_vtk.py: %s lanecast %.4f s/frame, VTK %.4f s/frame (x%.2f), PSNR between %.1f dB -> %s"
              % (name, lc_frame, vtk_frame, vtk_frame / lc_frame, psnr, comp))


if __name__ == "__main__":
    main()
