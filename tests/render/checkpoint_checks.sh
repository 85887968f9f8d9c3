#!/usr/bin/env bash
# The promises of `symphong render` in passes (render/progressive.h, render/checkpoint.h), run by CTest
# (tests/CMakeLists.txt) as
#   checkpoint_checks.sh CHECK BINARY
# Every comparison is byte for byte against the EXR of an uninterrupted one-pass render of the same
# settings. Checks:
#   passes        pass sizes 1, 5 and automatic, with every sampler and a spread-mode estimator
#   kill          kill -9 at pseudo-random moments (a fixed sequence, scaled to the time of the whole
#                 render here), --resume after each, until the render ends by itself (at least 10 kills, at
#                 most 25)
#   kill-writing  kill -9 while a checkpoint is being written (as soon as its temporary file appears),
#                 five times (at least one must land mid-write), --resume after each
#   sigterm       SIGTERM (what Slurm sends before it kills) and SIGINT: exit 143 / 130 with a checkpoint
#                 and a preview image, then --resume
#   refused       a checkpoint of other settings, of another scene, damaged or truncated: exit 2, one
#                 error naming the file and what differs, the checkpoint left as it was; an existing
#                 checkpoint without --resume; --resume with no checkpoint starts afresh and says so;
#                 a finished checkpoint gives its image at once
#   study-resume  a study stopped by SIGINT while rendering its reference writes reference.ckpt; --resume
#                 resumes it and ends with the rows of an uninterrupted study (times aside)
#   study-kill    a study killed with SIGKILL at pseudo-random moments (a fixed sequence of delays and of
#                 rows to wait for, so kills land in the reference and among the rows) and resumed each
#                 time with --resume ends with the rows of an uninterrupted study (times aside)
#   unwritable    the output directory becomes unwritable while a render with checkpoints runs: exit 2,
#                 one error naming the checkpoint, no temporary file left, and the last checkpoint intact
#                 (it resumes to the uninterrupted render's EXR). How: a tmpfs with room for one
#                 checkpoint, mounted in a private mount namespace (unshare -m as root, unshare -Urm
#                 otherwise), so the second checkpoint finds the disk full; where no namespace can be
#                 made, the directory is made read-only with chmod (not root) or replaced by a file
#                 (root, whom chmod does not stop) once the first checkpoint is there
#   stop-rules    --time stops with "time limit" and fewer samples than --spp; --target-error stops with
#                 "target error"
set -euo pipefail
check=$1 bin=$2
# shellcheck source=../signal_wait.sh
source "$(dirname "$0")/../signal_wait.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$work"
base=(render cornell -W 80 -H 60 -t 2)

# reference NAME ARGS...: the uninterrupted one-pass render, as NAME.
reference() {
  local name=$1
  shift
  "$bin" "${base[@]}" "$@" -o "$name" >/dev/null
}

case $check in
passes)
  for sampler in independent stratified sobol; do
    reference ref.exr --spp 24 --sampler "$sampler"
    for pass in 1 5 0; do
      "$bin" "${base[@]}" --spp 24 --sampler "$sampler" --pass-spp "$pass" --time 1e6 -o p.exr >out
      grep -q "24 of 24 spp (all)" out || fail "summary: $(cat out)"
      cmp ref.exr p.exr || fail "sampler $sampler, passes of $pass spp: the EXR differs from one pass"
    done
  done
  # Enough samples that the wavefront's batches meet the rare ray whose answer could depend on its batch (Embree's
  # occlusion packets did: this pass size differed from one pass then).
  reference ref.exr --spp 2000 --splitting none
  "$bin" "${base[@]}" --spp 2000 --splitting none --pass-spp 7 -o p.exr >/dev/null
  cmp ref.exr p.exr || fail "2000 spp in passes of 7: the EXR differs from one pass"
  # A branching first hit in the wavefront: its continuations' bounce rays share packets across camera samples.
  reference ref.exr --spp 1000 --splitting none --split 2
  "$bin" "${base[@]}" --spp 1000 --splitting none --split 2 --pass-spp 7 -o p.exr >/dev/null
  cmp ref.exr p.exr || fail "--split 2, 1000 spp in passes of 7: the EXR differs from one pass"
  reference ref.exr --spp 24 -e symmetric --symmetric-mode spread
  "$bin" "${base[@]}" --spp 24 -e symmetric --symmetric-mode spread --pass-spp 7 -o p.exr >/dev/null
  cmp ref.exr p.exr || fail "symmetric spread mode in passes of 7: the EXR differs from one pass"
  ;;
kill)
  reference ref.exr --spp 512
  # The kills' delays scale with this machine's time for the whole checkpointed render (a faster renderer, or
  # a less busy machine, must still be killed 10 times): up to a tenth of it, at least 20 ms.
  start=$(date +%s%N)
  "$bin" "${base[@]}" --spp 512 --pass-spp 2 --checkpoint whole.ckpt --checkpoint-interval 0.01 -o whole.exr >/dev/null
  span=$(( ($(date +%s%N) - start) / 10000000 ))
  [ "$span" -ge 30 ] || span=30
  RANDOM=20261202
  for attempt in $(seq 1 25); do
    "$bin" "${base[@]}" --spp 512 --pass-spp 2 --checkpoint c.ckpt --checkpoint-interval 0.01 --resume -o out.exr >/dev/null 2>err &
    pid=$!
    delay=$((20 + RANDOM % span))
    sleep "$((delay / 1000)).$(printf '%03d' $((delay % 1000)))"
    kill -9 "$pid" 2>/dev/null || true
    rc=0
    wait "$pid" 2>/dev/null || rc=$?
    [ "$rc" -eq 0 ] && break
    [ "$rc" -eq 137 ] || fail "attempt $attempt: exit code $rc: $(cat err)"
  done
  [ "$attempt" -ge 10 ] || fail "the render finished after $attempt attempts (delays up to $((20 + span)) ms): too few kills to test anything"
  "$bin" "${base[@]}" --spp 512 --pass-spp 2 --checkpoint c.ckpt --checkpoint-interval 0.01 --resume -o out.exr >/dev/null 2>err ||
    fail "the last resume failed: $(cat err)"
  cmp ref.exr out.exr || fail "killed $attempt times and resumed: the EXR differs from the uninterrupted one"
  ;;
kill-writing)
  # A large image, so that writing its checkpoint takes a while; killed the moment the temporary file of
  # a checkpoint appears (the rename has not happened yet).
  big=(render cornell -W 480 -H 360 -t 2 --spp 6)
  "$bin" "${big[@]}" -o ref.exr >/dev/null
  hits=0
  for attempt in $(seq 1 5); do
    "$bin" "${big[@]}" --pass-spp 1 --checkpoint c.ckpt --checkpoint-interval 0.01 --resume -o out.exr >/dev/null 2>err &
    pid=$!
    # Polled from Python (a bash loop forks a sleep each time, too slow to see a short write on a busy
    # machine): kill -9 the moment the checkpoint's temporary file exists; exit 0 when it was seen.
    if python3 - "$pid" ".c.ckpt.tmp-$pid" <<'PY'; then hits=$((hits + 1)); fi
import os, signal, sys, time
pid, tmp = int(sys.argv[1]), sys.argv[2]
deadline = time.monotonic() + 60
while time.monotonic() < deadline:
    if os.path.exists(tmp):
        os.kill(pid, signal.SIGKILL)
        sys.exit(0)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        sys.exit(1)
    time.sleep(0.0002)
sys.exit(1)
PY
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  # At least one kill must land while a checkpoint is being written (on a busy machine some land just
  # after the rename, or the poll misses a short write).
  [ "$hits" -ge 1 ] || fail "none of 5 kills came while a checkpoint was being written"
  "$bin" "${big[@]}" --pass-spp 1 --checkpoint c.ckpt --checkpoint-interval 0.01 --resume -o out.exr >/dev/null 2>err ||
    fail "resuming after kills in the middle of writing failed: $(cat err)"
  cmp ref.exr out.exr || fail "killed while writing checkpoints and resumed: the EXR differs"
  ;;
sigterm)
  reference ref.exr --spp 400
  for signal in TERM INT; do
    rm -f c.ckpt out.exr
    "$bin" "${base[@]}" --spp 400 --pass-spp 4 --checkpoint c.ckpt --checkpoint-interval 0.2 -o out.exr >out 2>err &
    pid=$!
    # The first checkpoint means the render is under way (its signal handlers installed).
    for _ in $(seq 1 3000); do
      [ -e c.ckpt ] && break
      sleep 0.01
    done
    [ -e c.ckpt ] || fail "SIG$signal: no checkpoint after 30 s"
    kill -s "$signal" "$pid"
    rc=0
    wait "$pid" || rc=$?
    expected=$([ "$signal" = TERM ] && echo 143 || echo 130)
    [ "$rc" -eq "$expected" ] || fail "SIG$signal: exit code $rc, expected $expected: $(cat err)"
    grep -q "interrupted by SIG$signal" out || fail "SIG$signal: summary: $(cat out)"
    grep -q -- "--resume continues from c.ckpt" err || fail "SIG$signal: stderr: $(cat err)"
    [ -s c.ckpt ] && [ -s out.exr ] || fail "SIG$signal: no checkpoint or no preview image"
    "$bin" "${base[@]}" --spp 400 --pass-spp 4 --checkpoint c.ckpt --resume -o out.exr >out 2>err || fail "resume: $(cat err)"
    grep -q "resuming from c.ckpt" err || fail "resume did not say so: $(cat err)"
    cmp ref.exr out.exr || fail "SIG$signal and resumed: the EXR differs"
  done
  ;;
refused)
  reference ref.exr --spp 16
  "$bin" "${base[@]}" --spp 16 --pass-spp 4 --checkpoint c.ckpt -o out.exr >/dev/null
  cp c.ckpt saved.ckpt
  # expect_refused PATTERN ARGS...: exit 2, one error on stderr matching PATTERN.
  expect_refused() {
    local pattern=$1 rc=0
    shift
    "$bin" "$@" >out 2>err || rc=$?
    [ "$rc" -eq 2 ] || fail "exit code $rc, expected 2 ($*): $(cat err)"
    [ "$(grep -c 'error:' err)" -eq 1 ] || fail "expected one error on stderr, got: $(cat err)"
    grep -q -- "$pattern" err || fail "message: $(cat err), expected /$pattern/"
  }
  expect_refused "c.ckpt: the checkpoint was made with seed 1, not 4" "${base[@]}" --seed 4 --spp 16 --checkpoint c.ckpt --resume -o o.exr
  expect_refused "c.ckpt: the checkpoint was made with spp 16, not 32" "${base[@]}" --spp 32 --checkpoint c.ckpt --resume -o o.exr
  expect_refused "c.ckpt: the checkpoint was made with estimator \"phong\", not \"cosine\"" \
    "${base[@]}" --spp 16 -e cosine --checkpoint c.ckpt --resume -o o.exr
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >tri.obj
  expect_refused "c.ckpt: the checkpoint is of another scene (cornell" \
    render tri.obj -W 80 -H 60 -t 2 --spp 16 --checkpoint c.ckpt --resume -o o.exr
  expect_refused "c.ckpt: a checkpoint is already there: add --resume" "${base[@]}" --spp 16 --checkpoint c.ckpt -o o.exr
  cmp c.ckpt saved.ckpt || fail "a refused resume changed the checkpoint"
  [ ! -e o.exr ] || fail "a refused resume wrote an image"
  # Damaged: one byte of the sums flipped; truncated; not a checkpoint at all.
  cp saved.ckpt d.ckpt
  printf '\x55' | dd of=d.ckpt bs=1 seek=$(($(stat -c %s d.ckpt) - 100)) conv=notrunc 2>/dev/null
  expect_refused "d.ckpt: not a usable checkpoint (its checksum does not match" "${base[@]}" --spp 16 --checkpoint d.ckpt --resume -o o.exr
  head -c 5000 saved.ckpt >t.ckpt
  expect_refused "t.ckpt: not a usable checkpoint (.*truncated" "${base[@]}" --spp 16 --checkpoint t.ckpt --resume -o o.exr
  echo hello >n.ckpt
  expect_refused "n.ckpt: not a usable checkpoint (it does not start with" "${base[@]}" --spp 16 --checkpoint n.ckpt --resume -o o.exr
  # A finished checkpoint: its image at once, the same bytes.
  "$bin" "${base[@]}" --spp 16 --checkpoint c.ckpt --resume -o again.exr >out 2>err
  cmp ref.exr again.exr || fail "the image of a finished checkpoint differs"
  grep -q "(0.00 s in this run)" out || fail "a finished checkpoint rendered again: $(cat out)"
  # --resume with no checkpoint yet: from the beginning, said on stderr; the default path is beside the output.
  "$bin" "${base[@]}" --spp 16 --resume -o fresh.exr >out 2>err
  grep -q "no checkpoint at fresh.exr.ckpt yet: starting from the beginning" err || fail "stderr: $(cat err)"
  [ -s fresh.exr.ckpt ] || fail "no checkpoint beside the output"
  cmp ref.exr fresh.exr || fail "a fresh --resume render differs"
  ;;
study-resume)
  study=(study cornell -e cosine,phong --spp 1,4 -R 2 -W 24 -H 24 --reference-spp 6000 --no-plots -t 2)
  "$bin" "${study[@]}" -o whole >/dev/null 2>&1
  "$bin" "${study[@]}" -o parts >/dev/null 2>err &
  pid=$!
  # A background job of a non-interactive shell starts with SIGINT ignored: a signal sent before the study
  # installs its handler is lost, and the study runs to the end (exit 0). Sent once SIGINT is caught, well
  # inside the 6000-spp reference.
  wait_until_caught "$pid" 2
  kill -INT "$pid"
  rc=0
  wait "$pid" || rc=$?
  [ "$rc" -eq 130 ] || fail "SIGINT during the reference: exit code $rc: $(cat err)"
  [ -s parts/reference.ckpt ] || fail "no reference checkpoint after SIGINT: $(ls parts)"
  "$bin" "${study[@]}" -o parts --resume >/dev/null 2>err || fail "resume failed: $(cat err)"
  grep -q "resuming the reference from parts/reference.ckpt" err || fail "the reference was not resumed: $(cat err)"
  [ ! -e parts/reference.ckpt ] || fail "the finished reference's checkpoint was left behind"
  cmp whole/reference.exr parts/reference.exr || fail "the resumed reference differs from the uninterrupted one"
  python3 - whole/results.json parts/results.json <<'PY' || fail "the rows differ"
import json, sys
timing = {"seconds", "cpu_seconds", "cost", "rays", "efficiency", "efficiency_relmse"}
a, b = (json.load(open(f))["rows"] for f in sys.argv[1:3])
assert len(a) == len(b), (len(a), len(b))
for x, y in zip(a, b):
    for k in x:
        assert k in timing or x[k] == y[k], (k, x[k], y[k])
PY
  ;;
study-kill)
  study=(study cornell -e cosine,phong --spp 2,8 -R 3 -W 24 -H 24 --reference-spp 2000 --no-plots --no-page -t 2)
  "$bin" "${study[@]}" -o whole >/dev/null 2>err || fail "the uninterrupted study failed: $(cat err)"
  rows=$(($(wc -l <whole/results.csv) - 1))
  # Each attempt runs the study with --resume and kills it with SIGKILL: attempt 1 after a delay within
  # the reference, the others once results.csv holds a pseudo-random number of rows (0 to all but one)
  # plus a pseudo-random 0-40 ms, so kills land in the reference, between rows and in the middle of a
  # row's render or of the writing of results; the attempt that finishes before its kill ends the loop.
  python3 - "$rows" "$bin" "${study[@]}" -o parts --resume <<'PY' || fail "the kills and resumes went wrong (above)"
import os, random, signal, subprocess, sys, time
rows, cmd = int(sys.argv[1]), sys.argv[2:]
rng = random.Random(20261203)
def rows_done():
    try:
        with open("parts/results.csv") as f:
            return max(0, sum(1 for _ in f) - 1)
    except OSError:
        return 0
kills = 0
for attempt in range(1, 16):
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=open("err", "w"))
    if attempt == 1:
        wait_rows, delay = 0, rng.uniform(0.05, 0.6)
    else:
        wait_rows, delay = rng.randint(0, rows - 1), rng.uniform(0.0, 0.04)
    deadline = time.monotonic() + 600
    while p.poll() is None and rows_done() < wait_rows and time.monotonic() < deadline:
        time.sleep(0.001)
    start = time.monotonic()
    while p.poll() is None and time.monotonic() - start < delay:
        time.sleep(0.001)
    if p.poll() is None:
        p.send_signal(signal.SIGKILL)
    rc = p.wait()
    print(f"attempt {attempt}: waited for {wait_rows} rows + {delay:.3f} s: exit {rc}, {rows_done()} rows kept")
    if rc == 0:
        break
    if rc != -signal.SIGKILL:
        sys.exit(f"attempt {attempt}: exit code {rc}: {open('err').read()}")
    kills += 1
if kills < 3:
    sys.exit(f"only {kills} kills landed before the study finished: too few to test anything")
if rc != 0:
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"the last resume failed: {r.stderr}")
PY
  [ ! -e parts/reference.ckpt ] || fail "the finished reference's checkpoint was left behind"
  cmp whole/reference.exr parts/reference.exr || fail "the reference after kills differs from the uninterrupted one"
  python3 - whole/results.json parts/results.json <<'PY' || fail "the rows differ from the uninterrupted study's"
import json, sys
timing = {"seconds", "cpu_seconds", "cost", "rays", "efficiency", "efficiency_relmse"}
a, b = (json.load(open(f))["rows"] for f in sys.argv[1:3])
assert len(a) == len(b), (len(a), len(b))
for x, y in zip(a, b):
    assert set(x) == set(y), (sorted(x), sorted(y))
    for k in x:
        assert k in timing or x[k] == y[k], (k, x[k], y[k])
PY
  ;;
unwritable)
  reference ref.exr --spp 256
  args=("${base[@]}" --spp 256 --pass-spp 1 --checkpoint-interval 0.01)
  # The sizes of a checkpoint and of an image of this render (one pass of it, stopped by --time).
  "$bin" "${args[@]}" --time 1e-9 --checkpoint one.ckpt -o one.exr >/dev/null
  ckpt=$(stat -c %s one.ckpt) img=$(stat -c %s one.exr)
  mkdir out
  if [ "$(id -u)" -eq 0 ]; then ns=(unshare -m); else ns=(unshare -Urm); fi
  if "${ns[@]}" true 2>/dev/null && "${ns[@]}" sh -c 'mount -t tmpfs -o size=64k tmpfs out' 2>/dev/null; then
    # A full disk: room for one checkpoint, the preview image and half a checkpoint (every write goes to a
    # temporary file first, so the second checkpoint needs a second checkpoint's room), in kilobytes.
    kb=$(((ckpt + img + ckpt / 2) / 1024 + 1))
    how="a full tmpfs of $kb KB"
    rc=0
    "${ns[@]}" bash -c 'mount -t tmpfs -o size="$1"k tmpfs out || exit 99
      shift
      rc=0
      "$@" --checkpoint out/c.ckpt -o out/out.exr >stdout 2>err || rc=$?
      cp out/c.ckpt kept.ckpt 2>/dev/null
      ls -A out >left
      exit "$rc"' -- "$kb" "$bin" "${args[@]}" || rc=$?
    [ "$rc" -ne 99 ] || fail "the tmpfs could be mounted once but not again"
  else
    # No mount namespace here: the directory becomes unwritable once the first checkpoint is in it.
    "$bin" "${args[@]}" --checkpoint out/c.ckpt -o out/out.exr >stdout 2>err &
    pid=$!
    for _ in $(seq 1 3000); do
      [ -e out/c.ckpt ] && break
      sleep 0.01
    done
    [ -e out/c.ckpt ] || fail "no first checkpoint after 30 s: $(cat err)"
    if [ "$(id -u)" -ne 0 ]; then
      how="chmod a-w"
      chmod a-w out
    else
      how="the directory replaced by a file"
      mv out out.moved && echo "not a directory" >out
    fi
    rc=0
    wait "$pid" || rc=$?
    if [ -d out.moved ]; then mv out.moved out.dir; else chmod u+w out; mv out out.dir; fi
    cp out.dir/c.ckpt kept.ckpt
    ls -A out.dir >left
  fi
  [ "$rc" -eq 2 ] || fail "$how: exit code $rc, expected 2: $(cat err)"
  [ "$(grep -c 'error:' err)" -eq 1 ] || fail "$how: expected one error on stderr, got: $(cat err)"
  grep -q "out/c.ckpt: cannot write\|out/out.exr: cannot write" err || fail "$how: the error does not name what could not be written: $(cat err)"
  # A full disk lets the temporary file be removed; a directory that became read-only (or went away)
  # while a checkpoint was being written cannot have it removed, and that is all it may leave.
  if [ "$how" != "chmod a-w" ] && [ "$how" != "the directory replaced by a file" ]; then
    ! grep -q '\.tmp-' left || fail "$how: a temporary file was left in the directory: $(cat left)"
  fi
  ! grep -v -q -E '^(c\.ckpt|out\.exr|\.c\.ckpt\.tmp-[0-9]+|\.out\.exr\.tmp-[0-9]+)$' left || fail "$how: unexpected files: $(cat left)"
  [ -s kept.ckpt ] || fail "$how: no checkpoint left: $(cat left)"
  # The last checkpoint is whole: it resumes (checksum and size checked) to the uninterrupted render.
  "$bin" "${args[@]}" --checkpoint kept.ckpt --resume -o resumed.exr >/dev/null 2>err || fail "$how: the kept checkpoint does not resume: $(cat err)"
  grep -q "resuming from kept.ckpt" err || fail "$how: the resume did not start from the kept checkpoint: $(cat err)"
  cmp ref.exr resumed.exr || fail "$how: resumed from the kept checkpoint, the EXR differs from the uninterrupted one"
  echo "($how)"
  ;;
stop-rules)
  "$bin" "${base[@]}" --spp 1000000 --time 1 -o t.exr >out
  grep -q "spp (time limit 1 s)" out || fail "summary: $(cat out)"
  "$bin" "${base[@]}" --spp 100000 --target-error 0.01 -o e.exr >out
  grep -q "spp (target error 1% reached)" out || fail "summary: $(cat out)"
  ;;
*)
  fail "unknown check $check"
  ;;
esac
echo "ok: $check"
