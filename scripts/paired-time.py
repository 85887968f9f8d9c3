#!/usr/bin/env python3
"""Times a command as a whole process, alone or paired against a second one, the way docs/performance.md's
side-by-side figures are taken: each run's CPU time (user + system, the kernel's own accounting of the
finished child and of the children it waited for, from wait4) and wall time (a monotonic clock around the
run), after warm-up runs that are not counted; with --vs, the two commands alternate (A B A B ...) and
the ratio A/B is taken pair by pair, so that a drift of the machine's speed during the call bends both
sides of a pair alike. Every figure is printed as min, median and max: quote the median.

    python3 scripts/paired-time.py [-n RUNS] [--warmup W] [--vs 'COMMAND_B'] -- COMMAND [ARG ...]

COMMAND_B is one string split as a shell splits words (shlex); neither command runs in a shell (write
sh -c '...' for a pipe or a redirection). Their output is discarded. --json prints the runs as JSON too.
Exit status 0 when every run was started and reaped (a command's own exit codes are printed, not acted
on), 2 on unusable arguments or a command that cannot start.
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import time


def run_once(argv):
    """One run of argv: (cpu seconds, wall seconds, peak resident KiB, exit code)."""
    start = time.perf_counter()
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    return usage.ru_utime + usage.ru_stime, wall, usage.ru_maxrss, proc.returncode


def spread(values):
    """(min, median, max) of a non-empty list."""
    return min(values), statistics.median(values), max(values)


def pair_ratios(a_runs, b_runs, key):
    """The ratio A/B of each pair (run i of A against run i of B) of figure `key` (0: cpu, 1: wall)."""
    return [a[key] / b[key] for a, b in zip(a_runs, b_runs) if b[key] > 0]


def summary_rows(a_runs, b_runs=None):
    """The printed table: (label, (min, median, max)) per figure."""
    rows = [("A cpu s", spread([r[0] for r in a_runs])), ("A wall s", spread([r[1] for r in a_runs]))]
    if b_runs:
        rows += [("B cpu s", spread([r[0] for r in b_runs])), ("B wall s", spread([r[1] for r in b_runs]))]
        for label, key in (("A/B cpu", 0), ("A/B wall", 1)):
            ratios = pair_ratios(a_runs, b_runs, key)
            if ratios:
                rows.append((label, spread(ratios)))
    rows.append(("A peak MiB", spread([r[2] / 1024 for r in a_runs])))
    if b_runs:
        rows.append(("B peak MiB", spread([r[2] / 1024 for r in b_runs])))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], usage=__doc__.split("\n\n")[1].strip())
    parser.add_argument("-n", "--runs", type=int, default=5, help="counted runs of each command (default 5)")
    parser.add_argument("--warmup", type=int, default=1, help="runs of each before counting (default 1)")
    parser.add_argument("--vs", help="the second command (B), one shell-quoted string")
    parser.add_argument("--json", action="store_true", help="print every run as JSON after the table")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="the command (A), after --")
    args = parser.parse_args(argv)
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command or args.runs < 1 or args.warmup < 0:
        parser.print_usage(sys.stderr)
        print("paired-time: need a command after --, RUNS >= 1 and WARMUP >= 0", file=sys.stderr)
        return 2
    other = shlex.split(args.vs) if args.vs else None
    commands = [command] + ([other] if other else [])
    try:
        for _ in range(args.warmup):
            for c in commands:
                run_once(c)
        runs = [[] for _ in commands]
        for _ in range(args.runs):
            for i, c in enumerate(commands):
                runs[i].append(run_once(c))
    except OSError as e:
        print(f"paired-time: cannot start {e.filename}: {e.strerror}", file=sys.stderr)
        return 2
    for label, (lo, mid, hi) in summary_rows(runs[0], runs[1] if other else None):
        print(f"{label:<12} {lo:>10.4f} {mid:>10.4f} {hi:>10.4f}")
    codes = sorted({r[3] for rs in runs for r in rs})
    print(f"exit codes   {' '.join(str(c) for c in codes)}   ({args.runs} runs each after {args.warmup} warm-up; min median max)")
    if args.json:
        names = ["A", "B"]
        print(json.dumps({names[i]: [dict(zip(("cpu", "wall", "peak_kib", "exit"), r)) for r in rs] for i, rs in enumerate(runs)}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
