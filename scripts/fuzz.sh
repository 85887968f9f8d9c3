#!/usr/bin/env bash
# Runs the fuzzing campaign of symphong's input loaders (fuzz/, docs/reliability.md): installs clang and
# its libFuzzer runtime when they are missing (apt-get, as root or through sudo, as scripts/setup.sh
# does), configures and builds the `fuzz` preset into build/fuzz, prepares the seed corpora
# (fuzz/make_corpus.py into build/fuzz/corpus/<target>, which keeps what earlier campaigns found), runs
# every fuzz target for SECONDS seconds and prints a summary per target: executions, exec/s, the final
# coverage (cov: edges, ft: features), corpus size and the number of crash, timeout and out-of-memory
# artifacts this campaign wrote (into build/fuzz/artifacts/<target>/, which keeps those of earlier
# campaigns; logs in build/fuzz/logs/<target>.log).
#
# Usage: scripts/fuzz.sh SECONDS [TARGET...]     (default: every target that was built)
# Environment: FUZZ_JOBS (targets run side by side, default 2), FUZZ_NICE (default 10: compiles and
# other work keep priority), FUZZ_ARGS (more libFuzzer flags).
#
# Each target runs under libFuzzer's -fork=1 with -ignore_crashes/-ignore_timeouts/-ignore_ooms, so a
# campaign goes on after a finding; -timeout=10 makes an input that takes over 10 s a finding, and
# -rss_limit_mb=2048 one that needs over 2 GiB. Reproduce one artifact with
#   build/fuzz/fuzz/<target> build/fuzz/artifacts/<target>/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."

if [ $# -lt 1 ] || ! [[ "$1" =~ ^[0-9]+$ ]]; then
  echo "usage: scripts/fuzz.sh SECONDS [TARGET...]" >&2
  exit 2
fi
seconds=$1
shift
jobs=${FUZZ_JOBS:-2}
nice_level=${FUZZ_NICE:-10}

# clang and libFuzzer's runtime (libclang-rt-14-dev on Debian 12 has libclang_rt.fuzzer).
. scripts/install-missing.sh
install_missing fuzz clang libclang-rt-14-dev

nice -n "$nice_level" cmake --preset fuzz >/dev/null
nice -n "$nice_level" cmake --build --preset fuzz

build=build/fuzz
python3 fuzz/make_corpus.py "$build/corpus"

if [ $# -gt 0 ]; then
  targets=("$@")
else
  targets=()
  for t in fuzz_obj fuzz_json fuzz_assimp fuzz_texture fuzz_ply fuzz_checkpoint fuzz_settings fuzz_gltf_ext; do
    [ -x "$build/fuzz/$t" ] && targets+=("$t")
  done
fi
mkdir -p "$build/logs"

run_target() {
  local t=$1
  mkdir -p "$build/artifacts/$t" "$build/corpus/$t"
  local dict=() extra=() asan=${ASAN_OPTIONS:-}
  [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  # Assimp 5.2 leaks memory on many malformed files (inside libassimp, docs/reliability.md): with leak
  # detection on (libFuzzer's per input, LeakSanitizer's at exit), nearly every job of fuzz_assimp would
  # end at its first leak instead of fuzzing on.
  if [ "$t" = fuzz_assimp ]; then
    extra=(-detect_leaks=0)
    asan="detect_leaks=0${asan:+:$asan}"
  fi
  # SYMPHONG_ASSIMP_IN_PROCESS=1: Assimp's importers in the fuzzer's own process, not first in a child
  # (scene/assimp_guard.cpp), so that the fuzzer sees and keeps the inputs that crash inside Assimp.
  # shellcheck disable=SC2086  # FUZZ_ARGS is a list of flags
  SYMPHONG_ASSIMP_IN_PROCESS=1 ASAN_OPTIONS=$asan nice -n "$nice_level" "$build/fuzz/$t" "$build/corpus/$t" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -artifact_prefix="$build/artifacts/$t/" -print_final_stats=1 "${dict[@]}" "${extra[@]}" ${FUZZ_ARGS:-} \
    >"$build/logs/$t.log" 2>&1 || true
}

stamp="$build/logs/.campaign-start"
touch "$stamp"  # the summary counts the artifacts of this campaign only
echo "fuzz: ${targets[*]}, ${seconds} s each, ${jobs} at a time (logs in $build/logs)"
running=0
for t in "${targets[@]}"; do
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait

# A target that crashed left its scratch directory (fuzz/fuzz_common.h) behind: remove those of processes
# that are gone.
for d in /dev/shm/symphong-fuzz-* "${TMPDIR:-/tmp}"/symphong-fuzz-*; do
  [ -d "$d" ] || continue
  pid=${d##*-}
  if [[ "$pid" =~ ^[0-9]+$ ]] && ! kill -0 "$pid" 2>/dev/null; then rm -rf "$d"; fi
done

# Summary: fork mode's last status line "#N: cov: C ft: F corp: K exec/s E oom/timeout/crash: a/b/c time: T".
printf '\n%-16s %10s %8s %7s %7s %6s %6s %8s %5s\n' target execs exec/s cov ft corpus crash timeout oom
for t in "${targets[@]}"; do
  log="$build/logs/$t.log"
  line=$(grep -E '^#[0-9]+: cov: ' "$log" | tail -1 || true)
  execs=$(sed -nE 's/^#([0-9]+):.*/\1/p' <<<"$line")
  cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$line")
  ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$line")
  secs=$(sed -nE 's/.* time: ([0-9]+)s.*/\1/p' <<<"$line")
  eps=""
  [ -n "$execs" ] && [ -n "$secs" ] && [ "$secs" -gt 0 ] && eps=$((execs / secs))  # the mean, not the last job's rate
  corpus=$(find "$build/corpus/$t" -type f | wc -l)
  crashes=$(find "$build/artifacts/$t" -newer "$stamp" \( -name 'crash-*' -o -name 'leak-*' -o -name 'deadly*' \) | wc -l)
  timeouts=$(find "$build/artifacts/$t" -newer "$stamp" -name 'timeout-*' | wc -l)
  ooms=$(find "$build/artifacts/$t" -newer "$stamp" -name 'oom-*' | wc -l)
  printf '%-16s %10s %8s %7s %7s %6s %6s %8s %5s\n' "$t" "${execs:-?}" "${eps:-?}" "${cov:-?}" "${ft:-?}" "$corpus" "$crashes" "$timeouts" "$ooms"
done
