#!/usr/bin/env bash
# The MPI promises of `symphong render` and `symphong study`, run by CTest (tests/CMakeLists.txt) as
#   mpi_checks.sh CHECK BINARY MPIEXEC [ARGS]
# with MPIEXEC the launcher and its flags (as root: --allow-run-as-root; on 2 cores: --oversubscribe).
# Checks:
#   identical NP SAMPLER   the EXR of NP ranks equals the single-process EXR byte for byte
#   missing                a missing scene under 2 ranks: exit 2, one line on stderr, no file
#   one-rank-fails         the scene is missing on rank 1 only: exit 2, rank 0 reports it once, no file
#   study                  a study under 2 ranks has the rows of a study without MPI (timings aside)
#   study-bad-input        a study's bad input under 2 ranks: exit 2, one message, no results
#   ears NP                --splitting ears under NP ranks (the learned factors shared, the records summed
#                          on rank 0): the single-process EXR byte for byte, in one go and in passes of 3
#                          spp, and stopped by --time under NP ranks and resumed under NP + 1; the image is
#                          not plain phong's (the factors did act)
#   study-interrupt        SIGINT to mpiexec during a study under 2 ranks: whole groups of rows kept,
#                          the report marked interrupted, rank 0 says so
#   rank-dies              rank 1 killed during a render: non-zero exit, rank 0 says so, no file
#   passes NP              passes of 3 spp under NP ranks: the single-process EXR byte for byte
#   resume NP1 NP2         NP1 ranks stopped by --time with a checkpoint, resumed with NP2 ranks (1: without
#                          mpiexec): the single-process EXR byte for byte
#   resume-kill            kill -9 of a 2-rank job (mpiexec and its ranks, one session) at four
#                          pseudo-random moments, resumed with 3 ranks after each: the single-process EXR
#   resume-sigterm         SIGTERM to mpiexec during a render of 2 ranks with a checkpoint: rank 0 writes it,
#                          3 ranks resume it to the single-process EXR
set -euo pipefail
check=$1 bin=$2 mpiexec=$3
# shellcheck source=../signal_wait.sh
source "$(dirname "$0")/../signal_wait.sh"
shift 3
read -r -a launch <<<"$mpiexec"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
render=(render cornell --spp 3 -W 70 -H 45 --seed 5 -t 1)

# expect_bad_input MESSAGE COMMAND...: exit code 2, MESSAGE as the only line on stderr, no $work/x.png.
expect_bad_input() {
  local message=$1 rc=0
  shift
  "$@" >"$work/out" 2>"$work/err" || rc=$?
  [ "$rc" -eq 2 ] || fail "exit code $rc, expected 2"
  [ "$(grep -c . "$work/err")" -eq 1 ] || fail "expected one line on stderr, got: $(cat "$work/err")"
  grep -qxF "$message" "$work/err" || fail "message: $(cat "$work/err")"
  [ ! -e "$work/x.png" ] || fail "an output file was created"
}

# live_in_session SID: the processes of session SID that are not yet dead (zombies left out), from /proc.
live_in_session() {
  local f stat rest
  for f in /proc/[0-9]*/stat; do
    read -r stat <"$f" 2>/dev/null || continue
    # After the command's ") ": state, parent, process group, session.
    read -r -a rest <<<"${stat##*) }"
    [ "${rest[3]}" = "$1" ] && [ "${rest[0]}" != Z ] && echo "${f//[!0-9]/}"
  done
  return 0
}

case $check in
identical)
  np=$1 sampler=$2
  "$bin" "${render[@]}" --sampler "$sampler" -o "$work/single.exr" >/dev/null
  "${launch[@]}" -np "$np" "$bin" "${render[@]}" --sampler "$sampler" -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "mpiexec -np $np failed: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "$np ranks, sampler $sampler: the EXR differs from the single-process one"
  [ "$(wc -l <"$work/out")" -eq 1 ] || fail "expected one summary line (rank 0), got: $(cat "$work/out")"
  [ "$np" -eq 1 ] || grep -q "$np ranks" "$work/out" || fail "the summary does not say $np ranks: $(cat "$work/out")"
  [ ! -s "$work/err" ] || fail "unexpected stderr: $(cat "$work/err")"
  ;;
missing)
  expect_bad_input "symphong: error: $work/missing.obj: no such file" \
    "${launch[@]}" -np 2 "$bin" render "$work/missing.obj" -o "$work/x.png"
  ;;
one-rank-fails)
  expect_bad_input "symphong: error: rank 1: $work/gone.obj: no such file" \
    "${launch[@]}" -np 1 "$bin" "${render[@]}" -o "$work/x.png" : -np 1 "$bin" render "$work/gone.obj" -o "$work/x.png"
  ;;
study)
  study=(study cornell --estimators cosine,phong --spp 1,2 -R 2 -W 16 -H 16 --reference-spp 16 --no-plots -t 1)
  "$bin" "${study[@]}" -o "$work/single" >/dev/null
  "${launch[@]}" -np 2 "$bin" "${study[@]}" -o "$work/mpi" >/dev/null 2>"$work/err" || fail "mpiexec study failed: $(cat "$work/err")"
  /usr/bin/python3 - "$work/single/results.json" "$work/mpi/results.json" <<'PY' || fail "the rows differ"
import json, sys
timing = {"seconds", "cpu_seconds", "cost", "efficiency", "efficiency_relmse"}
a, b = ([{k: v for k, v in r.items() if k not in timing} for r in json.load(open(p))["rows"]] for p in sys.argv[1:])
config = json.load(open(sys.argv[2]))["config"]
sys.exit(0 if a == b and len(a) == 8 and config["processes"] == 2 else 1)
PY
  ;;
study-rounds)
  # --target-interval's rounds of repeats under MPI: rank 0 decides each round and every rank renders it.
  # A target no study reaches and --max-repeats 4: the rounds are fixed, so the rows equal one process's.
  study=(study cornell --estimators cosine,phong --spp 1,2 -R 2 -W 16 -H 16 --reference-spp 16 --no-plots -t 1
         --target-interval 0.001 --max-repeats 4)
  "$bin" "${study[@]}" -o "$work/single" >/dev/null
  "${launch[@]}" -np 2 "$bin" "${study[@]}" -o "$work/mpi" >/dev/null 2>"$work/err" || fail "mpiexec study failed: $(cat "$work/err")"
  /usr/bin/python3 - "$work/single/results.json" "$work/mpi/results.json" <<'PY' || fail "the rows differ"
import json, sys
timing = {"seconds", "cpu_seconds", "cost", "efficiency", "efficiency_relmse"}
a, b = ([{k: v for k, v in r.items() if k not in timing} for r in json.load(open(p))["rows"]] for p in sys.argv[1:])
mpi = json.load(open(sys.argv[2]))
sys.exit(0 if a == b and len(a) == 2 * 2 + 2 * 4 and mpi["stopped_by"] == "max-repeats" and mpi["config"]["processes"] == 2 else 1)
PY
  ;;
study-bad-input)
  expect_bad_input "symphong: error: $work/missing.obj: no such file" \
    "${launch[@]}" -np 2 "$bin" study "$work/missing.obj" -o "$work/st"
  [ ! -e "$work/st/results.csv" ] || fail "results.csv was created"
  ;;
ears)
  np=$1 learn=(render cornell --spp 16 -W 70 -H 45 --seed 5 -t 1 --splitting ears)
  "$bin" "${learn[@]}" -o "$work/single.exr" >/dev/null
  "$bin" render cornell --spp 16 -W 70 -H 45 --seed 5 -t 1 --splitting none -o "$work/plain.exr" >/dev/null
  ! cmp -s "$work/single.exr" "$work/plain.exr" || fail "--splitting ears rendered plain phong's image"
  for passes in "" "--pass-spp 3"; do
    # shellcheck disable=SC2086
    "${launch[@]}" -np "$np" "$bin" "${learn[@]}" $passes -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
      fail "mpiexec -np $np ${passes:-(one pass)} failed: $(cat "$work/err")"
    grep -q "$np ranks" "$work/out" || fail "summary: $(cat "$work/out")"
    cmp "$work/single.exr" "$work/mpi.exr" || fail "$np ranks ${passes:-(one pass)}: the EXR differs from the single-process one"
  done
  # The sun scene's EARS rests after its third epoch (splitting/learning.h kRestBelowExtraPaths): rank 0's
  # decision reaches every rank, and the rest of the render is one segment.
  sun=(render "$(dirname "$0")/../../scenes/regime/sun-n10.json" --spp 32 -W 64 -H 48 --seed 5 -t 1 --splitting ears)
  "$bin" "${sun[@]}" -o "$work/single.exr" >/dev/null
  "${launch[@]}" -np "$np" "$bin" "${sun[@]}" --pass-spp 3 -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "mpiexec -np $np on the sun scene failed: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "$np ranks on the sun scene (EARS rests): the EXR differs from the single-process one"
  long=(render cornell --spp 400 -W 64 -H 48 --seed 5 -t 1 --splitting ears --pass-spp 2 --checkpoint "$work/c.ckpt")
  "$bin" "${long[@]}" -o "$work/single.exr" >/dev/null
  rm -f "$work/c.ckpt"
  "${launch[@]}" -np "$np" "$bin" "${long[@]}" --time 0.3 -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "the first run failed: $(cat "$work/err")"
  grep -q "spp (time limit" "$work/out" || fail "the first run was not stopped by --time: $(cat "$work/out")"
  "${launch[@]}" -np $((np + 1)) "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "resume failed: $(cat "$work/err")"
  grep -q "resuming from" "$work/err" || fail "the second run did not resume: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "$np ranks, then $((np + 1)), with ears: the EXR differs from the single-process one"
  ;;
study-interrupt)
  # Long enough to be interrupted after its first rows; short tiles, so that it stops within the second
  # that mpirun leaves between SIGTERM and SIGKILL.
  "${launch[@]}" -np 2 "$bin" study cornell --estimators cosine,phong --spp 1,2,4,8,16,32,64,128,256,512,1024 -R 2 -W 32 -H 32 \
    --reference-spp 64 --no-plots -t 1 -o "$work/st" >"$work/out" 2>"$work/err" &
  launcher=$!
  for _ in $(seq 600); do
    [ "$(cat "$work/st/results.csv" 2>/dev/null | wc -l)" -ge 3 ] && break
    sleep 0.1
  done
  kill -INT "$launcher"
  rc=0
  wait "$launcher" || rc=$?
  [ "$rc" -ne 0 ] || fail "exit code 0 after an interruption"
  rows=$(($(wc -l <"$work/st/results.csv") - 1))
  [ "$rows" -ge 2 ] && [ $((rows % 2)) -eq 0 ] || fail "$rows rows kept: expected whole groups of 2"
  [ "$rows" -lt 44 ] || fail "the study finished before it was interrupted"
  grep -qxF "symphong: interrupted; $rows finished row(s) kept in $work/st/results.csv (--resume continues)" "$work/err" ||
    fail "rank 0's message: $(cat "$work/err")"
  grep -qF '**Interrupted**' "$work/st/report.md" || fail "the report does not say it was interrupted"
  ;;
rank-dies)
  "${launch[@]}" -np 2 "$bin" render cornell --spp 4096 -W 64 -H 64 -t 1 -o "$work/x.png" >"$work/out" 2>"$work/err" &
  launcher=$!
  victim= survivor=
  for _ in $(seq 300); do
    for pid in $(pgrep -f "^$bin render" || true); do
      tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1 && victim=$pid
      tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=0 && survivor=$pid
    done
    [ -n "$victim" ] && [ -n "$survivor" ] && break
    sleep 0.1
  done
  [ -n "$victim" ] || fail "rank 1 was not found"
  [ -n "$survivor" ] || fail "rank 0 was not found"
  # Rank 0 says why the job stopped from its SIGTERM handler (the launcher's SIGTERM when a rank ends):
  # killed before it installs that handler, it said nothing. Rank 1 goes once rank 0 catches SIGTERM, well
  # inside the 4096-spp render.
  wait_until_caught "$survivor" 15
  kill -KILL "$victim"
  rc=0
  wait "$launcher" || rc=$?
  [ "$rc" -ne 0 ] || fail "exit code 0 after a rank died"
  grep -qxF "symphong: the MPI launcher is stopping the job (Ctrl-C, or a rank ended)" "$work/err" || fail "rank 0's message: $(cat "$work/err")"
  [ ! -e "$work/x.png" ] || fail "an output file was created"
  ;;
passes)
  np=$1 passes=(render cornell --spp 20 -W 70 -H 45 --seed 5 -t 1)
  "$bin" "${passes[@]}" -o "$work/single.exr" >/dev/null
  "${launch[@]}" -np "$np" "$bin" "${passes[@]}" --pass-spp 3 -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "mpiexec -np $np failed: $(cat "$work/err")"
  grep -q "20 of 20 spp (all).*$np ranks" "$work/out" || fail "summary: $(cat "$work/out")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "$np ranks in passes: the EXR differs from the single-process one"
  ;;
resume)
  first=$1 second=$2
  long=(render cornell --spp 400 -W 64 -H 48 --seed 5 -t 1 --pass-spp 2 --checkpoint "$work/c.ckpt")
  "$bin" "${long[@]}" -o "$work/single.exr" >/dev/null
  rm -f "$work/c.ckpt"
  "${launch[@]}" -np "$first" "$bin" "${long[@]}" --time 0.5 -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
    fail "the first run failed: $(cat "$work/err")"
  grep -q "spp (time limit" "$work/out" || fail "the first run was not stopped by --time: $(cat "$work/out")"
  if [ "$second" -eq 1 ]; then
    "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" || fail "resume failed: $(cat "$work/err")"
  else
    "${launch[@]}" -np "$second" "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" ||
      fail "resume failed: $(cat "$work/err")"
  fi
  grep -q "resuming from" "$work/err" || fail "the second run did not resume: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "$first ranks, then $second: the EXR differs from the single-process one"
  ;;
resume-kill)
  long=(render cornell --spp 600 -W 64 -H 48 --seed 5 -t 1 --pass-spp 2 --checkpoint "$work/c.ckpt" --checkpoint-interval 0.02)
  "$bin" "${long[@]}" -o "$work/single.exr" >/dev/null
  rm -f "$work/c.ckpt"
  RANDOM=4242
  for attempt in 1 2 3 4; do
    np=$((attempt % 2 + 2))
    before=$(stat -c "%i %y" "$work/c.ckpt" 2>/dev/null || echo none)
    setsid "${launch[@]}" -np "$np" "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" &
    pid=$!
    # Kill at a pseudo-random moment after this job has written a checkpoint of its own (a fixed delay from
    # the launch missed every checkpoint on a loaded machine, where starting mpiexec takes over a second).
    for _ in $(seq 1 6000); do
      [ "$(stat -c "%i %y" "$work/c.ckpt" 2>/dev/null || echo none)" != "$before" ] && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.01
    done
    sleep "0.$(printf '%03d' $((RANDOM % 400)))"
    # The whole job: Open MPI starts each rank in a process group of its own, so killing mpiexec's group
    # left the ranks running for up to a second, rank 0 renaming its checkpoint over the one that the
    # next job was reading. Every process of the session setsid made for mpiexec, as a node that fails.
    victims=$(live_in_session "$pid")
    # shellcheck disable=SC2086
    kill -9 $victims 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    # No rank of the killed job may live on (it would write the checkpoint under the next one).
    for _ in $(seq 1 100); do
      [ -z "$(live_in_session "$pid")" ] && break
      # shellcheck disable=SC2046
      kill -9 $(live_in_session "$pid") 2>/dev/null || true
      sleep 0.05
    done
    [ -z "$(live_in_session "$pid")" ] || fail "processes of the killed job are still running: $(live_in_session "$pid")"
  done
  [ -e "$work/c.ckpt" ] || fail "no checkpoint was written before the kills"
  "${launch[@]}" -np 3 "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" || fail "resume failed: $(cat "$work/err")"
  grep -q "resuming from" "$work/err" || fail "the last run did not resume: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "killed under 2 and 3 ranks, resumed under 3: the EXR differs"
  ;;
resume-sigterm)
  long=(render cornell --spp 800 -W 64 -H 48 --seed 5 -t 1 --pass-spp 4 --checkpoint "$work/c.ckpt" --checkpoint-interval 0.3)
  "$bin" "${long[@]}" -o "$work/single.exr" >/dev/null
  rm -f "$work/c.ckpt"
  "${launch[@]}" -np 2 "$bin" "${long[@]}" -o "$work/mpi.exr" >"$work/out" 2>"$work/err" &
  pid=$!
  for _ in $(seq 1 3000); do
    [ -e "$work/c.ckpt" ] && break
    sleep 0.01
  done
  [ -e "$work/c.ckpt" ] || fail "no checkpoint after 30 s"
  kill -TERM "$pid"
  wait "$pid" || true
  grep -q "interrupted by SIGTERM" "$work/out" || fail "rank 0 did not stop on SIGTERM: $(cat "$work/out") $(cat "$work/err")"
  "${launch[@]}" -np 3 "$bin" "${long[@]}" --resume -o "$work/mpi.exr" >"$work/out" 2>"$work/err" || fail "resume failed: $(cat "$work/err")"
  cmp "$work/single.exr" "$work/mpi.exr" || fail "stopped by SIGTERM under 2 ranks, resumed under 3: the EXR differs"
  ;;
*) fail "unknown check $check" ;;
esac
echo "ok: $check $*"
