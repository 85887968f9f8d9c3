"""Runtime behaviour: Ctrl-C cancels, the GIL is released, no references leak, the install rule works."""
import gc
import os
import pathlib
import subprocess
import sys
import textwrap
import threading
import time
import tracemalloc
import weakref

import numpy as np
import pytest

MODULE_DIR = os.environ.get("PYTHONPATH", "")


def run_python(code, **env):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=300,
                          env={**os.environ, **env})


def test_ctrl_c_cancels_a_render():
    """SIGINT half a second into a render that would take minutes raises KeyboardInterrupt promptly: the
    render stops after the tiles in flight (16x16 pixels x 256 spp: well under a second each here)."""
    p = run_python("""
        import os, signal, threading, time, symphong
        scene = symphong.load_scene('cornell')
        full = 4096 * 4096 * 256  # camera samples: minutes on any machine this runs on
        threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
        t0 = time.monotonic()
        try:
            symphong.render(scene, spp=256, width=4096, height=4096, threads=2)
            print('finished')
        except KeyboardInterrupt:
            print('interrupted', time.monotonic() - t0)
        img, _ = symphong.render(scene, spp=1, width=8, height=8)  # the module still works afterwards
        print('after', img.shape)
    """)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.split("\n")
    assert lines[0].startswith("interrupted"), p.stdout
    assert float(lines[0].split()[1]) < 30
    assert lines[1] == "after (8, 8, 3)"


def test_ctrl_c_cancels_a_study_and_keeps_rows(tmp_path):
    p = run_python(f"""
        import os, signal, threading, symphong
        threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT)).start()
        try:
            symphong.study(estimators='cosine', spp=[1], repeats=1000, width=64, height=64, reference_spp=4,
                           plots=False, out={str(tmp_path)!r})
            print('finished')
        except KeyboardInterrupt:
            print('interrupted')
    """)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "interrupted", p.stdout
    rows = (tmp_path / "results.csv").read_text().strip().split("\n")
    assert 1 <= len(rows) < 1001  # header, then the finished rows


def test_keyboard_interrupt_uncaught_exits_like_python():
    p = run_python("""
        import os, signal, threading, symphong
        threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
        symphong.furnace(estimators='all', grid=True, repeats=10_000_000)
    """)
    assert p.returncode != 0
    assert "KeyboardInterrupt" in p.stderr


def test_gil_is_released_during_a_render(sym):
    scene = sym.load_scene("cornell")
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.002)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.05)
    t0 = time.monotonic()
    _, stats = sym.render(scene, spp=64, width=128, height=128, threads=1)
    t1 = time.monotonic()
    stop.set()
    t.join()
    during = [x for x in ticks if t0 < x < t1]
    assert t1 - t0 > 0.2, "the render is too short to tell"
    # With the GIL held the thread could not tick at all until the render returned.
    assert len(during) >= 10, (len(during), t1 - t0)


def test_renders_in_parallel_python_threads(sym):
    scene = sym.load_scene("cornell")
    results = {}

    def work(seed):
        results[seed] = sym.render(scene, spp=2, width=32, height=32, seed=seed, threads=1)[0]

    threads = [threading.Thread(target=work, args=(s,)) for s in (1, 2, 3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for s in (1, 2, 3):
        assert np.array_equal(results[s], sym.render(scene, spp=2, width=32, height=32, seed=s)[0])


def test_no_leak_over_100_renders(sym):
    scene = sym.load_scene("cornell")
    refs_before = sys.getrefcount(scene)
    for _ in range(5):  # warm up caches (estimator tables, NumPy internals)
        sym.render(scene, spp=1, width=16, height=16, variance=True)
    gc.collect()
    tracemalloc.start()
    base, _ = tracemalloc.get_traced_memory()
    dead = []
    for _ in range(100):
        img, stats, var = sym.render(scene, spp=1, width=16, height=16, variance=True)
        dead.append(weakref.ref(img))
        dead.append(weakref.ref(var))
        assert sys.getrefcount(img) == 2 and sys.getrefcount(stats) == 2
        del img, stats, var
    gc.collect()
    grown = tracemalloc.get_traced_memory()[0] - base
    tracemalloc.stop()
    assert all(r() is None for r in dead), "an array outlived its last reference"
    assert sys.getrefcount(scene) == refs_before
    # 100 leaked images + variances would hold 100 x 2 x 3 KiB; the weakrefs themselves take about 15 KiB.
    assert grown < 40_000, grown


def test_cmake_install_puts_the_module_in_site_packages(tmp_path):
    build = os.environ.get("SYMPHONG_BUILD_DIR")
    if not build:
        pytest.skip("SYMPHONG_BUILD_DIR not set (CTest sets it)")
    subprocess.run(["cmake", "--install", build, "--component", "python"], check=True, capture_output=True,
                   env={**os.environ, "DESTDIR": str(tmp_path)})
    installed = list(tmp_path.rglob("symphong*.so"))
    assert len(installed) == 1, installed
    site = installed[0].parent
    assert site.name in ("site-packages", "dist-packages"), site
    p = subprocess.run([sys.executable, "-c", "import symphong; print(symphong.__file__)"], capture_output=True, text=True,
                       env={**os.environ, "PYTHONPATH": str(site)})
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == str(installed[0])
