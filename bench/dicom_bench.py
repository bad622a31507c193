#!/usr/bin/python3
"""Time to load a 512 x 512 x 300 CT series (docs/bench/dicom.md): lanecast
(`lanecast info`, whose load line times lc_volume_load alone, and the whole
process) against pydicom reading the same files into a NumPy volume (headers,
sort by position along the normal, stack, rescale to float32).

usage: dicom_bench.py LANECAST WORK_DIR [REPEATS]

Writes the series into WORK_DIR/ct512 once (pydicom, 12 bits stored in 16,
slope 1, intercept -1024, 0.7 mm pixels, 1.25 mm slices, files named in a
shuffled order), and a gdcmconv --rle copy in WORK_DIR/ct512_rle when
gdcmconv exists, then prints one line per reader and input: the median and
range of REPEATS (default 5) runs, after one warm-up run (page cache warm)."""
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np
import pydicom
from pydicom.dataset import FileDataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian

lanecast, work = sys.argv[1], sys.argv[2]
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 5
N, NZ = 512, 300
ct = os.path.join(work, "ct512")


def write():
    os.makedirs(ct)
    rng = np.random.default_rng(1)
    names = rng.permutation(NZ)
    y, x = np.mgrid[0:N, 0:N]
    body = ((x - 256) ** 2 + (y - 256) ** 2 < 230 ** 2)
    series = "1.2.826.0.1.3680043.10.1029.9000"
    for k in range(NZ):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"
        meta.MediaStorageSOPInstanceUID = "%s.%d" % (series, k + 1)
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        path = os.path.join(ct, "IM%04d" % names[k])
        ds = FileDataset(path, {}, file_meta=meta, preamble=b"\0" * 128)
        ds.is_little_endian, ds.is_implicit_VR = True, False
        ds.SOPClassUID, ds.SOPInstanceUID = meta.MediaStorageSOPClassUID, meta.MediaStorageSOPInstanceUID
        ds.SeriesInstanceUID, ds.Modality = series, "CT"
        ds.Rows = ds.Columns = N
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 12, 11, 0
        ds.PixelSpacing = [0.7, 0.7]
        ds.ImageOrientationPatient = [1, 0, 0, 0, 1, 0]
        ds.ImagePositionPatient = [-179.2, -179.2, -200.0 + 1.25 * k]
        ds.RescaleSlope, ds.RescaleIntercept = 1, -1024
        v = np.where(body, 1024 + 40 + ((x + y + k) % 200), 0) + rng.integers(0, 20, size=(N, N))
        ds.PixelData = v.astype(np.uint16).tobytes()
        ds.save_as(path, write_like_original=False)


def pydicom_load(folder):
    ds = [pydicom.dcmread(os.path.join(folder, f)) for f in os.listdir(folder)]
    iop = np.array(ds[0].ImageOrientationPatient, float)
    n = np.cross(iop[:3], iop[3:])
    ds.sort(key=lambda d: float(np.dot(np.array(d.ImagePositionPatient, float), n)))
    vol = np.stack([d.pixel_array for d in ds])
    return vol.astype(np.float32) * float(ds[0].RescaleSlope) + float(ds[0].RescaleIntercept)


def lanecast_load(folder):
    """(wall, CPU of the process, lanecast's own load line)"""
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run([lanecast, "info", folder], capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
    m = re.search(r"load\s+([0-9.]+) s", r.stdout)
    return wall, cpu, float(m.group(1)) if m else float("nan")


def report(name, times):
    print("%-44s median %.3f s  (%.3f .. %.3f, %d runs)" % (name, statistics.median(times), min(times), max(times),
                                                         len(times)))


if not os.path.isdir(ct):
    write()
inputs = [("ct512", ct)]
if shutil.which("gdcmconv"):
    rle = os.path.join(work, "ct512_rle")
    if not os.path.isdir(rle):
        os.makedirs(rle)
        for f in os.listdir(ct):
            subprocess.run(["gdcmconv", "--rle", os.path.join(ct, f), os.path.join(rle, f)], check=True)
    inputs.append(("ct512_rle", rle))
print("load average at the start: %.1f %.1f %.1f (2 cores)" % os.getloadavg())
for name, folder in inputs:
    lanecast_load(folder)
    runs = [lanecast_load(folder) for _ in range(repeats)]
    report("lanecast info %s (process, wall)" % name, [r[0] for r in runs])
    report("lanecast info %s (process, CPU)" % name, [r[1] for r in runs])
    report("lanecast info %s (load line, wall)" % name, [r[2] for r in runs])
    try:
        pydicom_load(folder)
    except Exception as e:  # pydicom 2.3 decodes RLE itself; other syntaxes need plug-ins
        print("pydicom %s: %s" % (name, e))
        continue
    wall, cpu = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        pydicom_load(folder)
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    report("pydicom %s (read, sort, rescale; wall)" % name, wall)
    report("pydicom %s (read, sort, rescale; CPU)" % name, cpu)
print("load average at the end: %.1f %.1f %.1f" % os.getloadavg())
