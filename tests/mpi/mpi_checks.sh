#!/usr/bin/env bash
# The MPI promises of `symphong render` and `symphong study`, run by CTest (tests/CMakeLists.txt) as
#   mpi_checks.sh CHECK BINARY MPIEXEC [ARGS]
# with MPIEXEC the launcher and its flags (as root: --allow-run-as-root; on 2 cores: --oversubscribe).
# Checks:
#   identical NP SAMPLER   the EXR of NP ranks equals the single-process EXR byte for byte
#   missing                a missing scene under 2 ranks: exit 2, one line on stderr, no file
#   one-rank-fails         the scene is missing on rank 1 only: exit 2, rank 0 reports it once, no file
#   study                  a study under 2 ranks has the rows of a study without MPI (timings aside)
set -euo pipefail
check=$1 bin=$2 mpiexec=$3
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
timing = {"seconds", "efficiency", "efficiency_relmse"}
a, b = ([{k: v for k, v in r.items() if k not in timing} for r in json.load(open(p))["rows"]] for p in sys.argv[1:])
sys.exit(0 if a == b and len(a) == 8 else 1)
PY
  ;;
*) fail "unknown check $check" ;;
esac
echo "ok: $check $*"
