"""scripts/paired-time.py, the side-by-side timer that docs/performance.md names: its ratios are taken pair by
pair (checked against hand-computed values), its CPU time counts the children that a command waits for (a
shell running the work in a child), and bad input is refused with exit 2. No assertion depends on how fast
this machine is: the CPU-time checks compare a command's CPU time with a bound far below what it burns."""
import importlib.util
import pathlib
import statistics
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "paired-time.py"

spec = importlib.util.spec_from_file_location("paired_time", SCRIPT)
paired_time = importlib.util.module_from_spec(spec)
spec.loader.exec_module(paired_time)


def test_ratios_are_taken_pair_by_pair_and_summarised_by_their_median():
    a = [(2.0, 4.0, 10, 0), (3.0, 3.0, 10, 0), (9.0, 9.0, 10, 0)]
    b = [(1.0, 2.0, 20, 0), (3.0, 1.0, 20, 0), (3.0, 9.0, 20, 0)]
    assert paired_time.pair_ratios(a, b, 0) == [2.0, 1.0, 3.0]
    assert paired_time.pair_ratios(a, b, 1) == [2.0, 3.0, 1.0]
    rows = dict(paired_time.summary_rows(a, b))
    assert rows["A/B cpu"] == (1.0, 2.0, 3.0)
    # The median of the ratios, not the ratio of the medians (3.0 / 3.0 = 1.0 here).
    assert rows["A/B cpu"][1] != statistics.median([r[0] for r in a]) / statistics.median([r[0] for r in b])
    assert rows["A cpu s"] == (2.0, 3.0, 9.0)
    assert rows["B peak MiB"] == (20 / 1024, 20 / 1024, 20 / 1024)


BURN = "import time\nt = time.process_time()\nwhile time.process_time() - t < 0.3: pass\n"


def test_cpu_time_counts_a_child_that_the_command_waits_for():
    # A shell whose child burns 0.3 s of CPU: the shell itself uses almost none.
    cpu, wall, peak, code = paired_time.run_once(["sh", "-c", f'"{sys.executable}" -c "{BURN}"'])
    assert code == 0
    assert cpu >= 0.25, cpu
    assert wall >= cpu * 0.5
    assert peak > 0


def test_the_command_line_prints_every_figure_and_the_exit_codes():
    p = subprocess.run([sys.executable, str(SCRIPT), "-n", "2", "--warmup", "0", "--vs", "sh -c 'exit 3'", "--", "true"],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    labels = [line.split("  ")[0].strip() for line in p.stdout.splitlines()]
    for label in ["A cpu s", "A wall s", "B cpu s", "B wall s", "A/B wall", "A peak MiB", "B peak MiB"]:
        assert label in labels, p.stdout
    assert "exit codes   0 3" in p.stdout


def test_bad_input_is_refused_with_exit_2():
    missing = subprocess.run([sys.executable, str(SCRIPT), "-n", "1", "--", "/nonexistent/command"], capture_output=True, text=True,
                             timeout=60)
    assert missing.returncode == 2
    assert "/nonexistent/command" in missing.stderr
    nothing = subprocess.run([sys.executable, str(SCRIPT)], capture_output=True, text=True, timeout=60)
    assert nothing.returncode == 2
    assert "need a command" in nothing.stderr
