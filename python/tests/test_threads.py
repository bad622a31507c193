"""Threads and signals: renders from several Python threads equal serial ones, the GIL is
released during renders (another thread runs), Ctrl-C cancels a render within 0.1 s with
KeyboardInterrupt and leaves the device usable."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import lanecast as lc

rng = np.random.default_rng(11)
POS = (rng.normal(size=(3000, 3)) * 5).astype(np.float32)
BIG = rng.random((128, 128, 128)).astype(np.float32)
# A render stops within the tiles being rendered, so the latency is a tile's time: where
# kernels are slow (the scalar target, the sanitizer build) the long renders of the Ctrl-C
# tests use small tiles so that one stays well under the 0.1 s they allow; elsewhere the
# default tiles (a 32x32 tile of this scene takes a few ms on avx2).
SLOW = os.environ.get("LANECAST_SANITIZED") == "1" or lc.Device().target == "scalar"
TILE = 8 if SLOW else 0


def scenes(dev):
    return [lc.Particles(dev, POS, radii=0.6), lc.Grid(dev, BIG[:40, :50, :60], copy=True),
            lc.RBFSet(dev, POS[:200] / 2, np.full(200, 0.8), np.ones(200))]


def test_threads_equal_serial(dev):
    vols = scenes(dev)
    tf = lc.TransferFunction.preset("heat", 1, 0.5)
    jobs = [(v, view) for v in vols for view in [(0, 10), (60, 30), (120, -20), (200, 45)]]
    serial = [np.asarray(lc.render(v, tf, 48, 40, view=view)) for v, view in jobs]
    results = [None] * len(jobs)
    devices = [lc.Device() for _ in range(4)]

    def work(t, shared):
        for n in range(t, len(jobs), 4):
            v, view = jobs[n]
            d = dev if shared else devices[t]  # one shared device (calls wait for each other) or one each
            results[n] = np.asarray(lc.render(v, tf, 48, 40, view=view, device=d))

    for shared in (False, True):
        results[:] = [None] * len(jobs)
        threads = [threading.Thread(target=work, args=(t, shared)) for t in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for n in range(len(jobs)):
            np.testing.assert_array_equal(results[n], serial[n])


def long_grid(dev):
    return lc.Grid(dev, BIG, copy=True)


def test_gil_released_during_render(dev):
    g = long_grid(dev)
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.02)
    t0 = time.monotonic()
    img = lc.render(g, width=256, height=256, method="brute", dt=0.1)
    t1 = time.monotonic()
    stop.set()
    t.join()
    assert t1 - t0 > 0.1, "the render must be long enough for the check to mean anything"
    # the ticker ran throughout the call: ticks in every quarter of it (with the GIL held by
    # the C call there would be none after its start)
    quarters = {int(4 * (x - t0) / (t1 - t0)) for x in ticks if t0 < x < t1}
    assert quarters == {0, 1, 2, 3}, (sorted(quarters), t1 - t0)
    assert img.stats["rays"] > 0


def interrupt_after(delay, box):
    def send():
        time.sleep(delay)
        box["sent"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)
    t = threading.Thread(target=send)
    t.start()
    return t


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals need the main thread")
def test_ctrl_c_cancels_a_render(dev):
    g = long_grid(dev)
    small = np.asarray(lc.render(g, width=32, height=32))
    before = signal.getsignal(signal.SIGINT)
    box = {}
    t = interrupt_after(0.3, box)
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        lc.render(g, width=1024, height=1024, method="brute", dt=0.05, tile=TILE)  # ~10 s uncancelled
    late = time.monotonic() - box["sent"]
    t.join()
    assert time.monotonic() - t0 > 0.25  # it did run until the signal
    assert late < 0.1, f"KeyboardInterrupt came {late:.3f} s after SIGINT"
    assert signal.getsignal(signal.SIGINT) is before  # Python's handler is back
    np.testing.assert_array_equal(np.asarray(lc.render(g, width=32, height=32)), small)  # the device still works


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals need the main thread")
def test_sigint_with_a_handler_that_does_not_raise(dev):
    g = long_grid(dev)
    seen = []
    old = signal.signal(signal.SIGINT, lambda s, f: seen.append(s))
    try:
        box = {}
        t = interrupt_after(0.2, box)
        with pytest.raises(lc.CancelledError):
            lc.render(g, width=1024, height=1024, method="brute", dt=0.05, tile=TILE)
        t.join()
        assert seen == [signal.SIGINT]  # the user's handler ran once
        assert time.monotonic() - box["sent"] < 0.1
    finally:
        signal.signal(signal.SIGINT, old)
