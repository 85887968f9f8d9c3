#!/usr/bin/env bash
# Writes the golden images of tests/golden/cases.txt with the program given (default build/release/symphong)
# and the CPU signature they were made on (tests/golden/cpu.txt). Run from anywhere; only when a change of
# the pictures is intended, and say so in the commit.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${1:-$root/build/release/symphong}"
cd "$root"
mkdir -p tests/golden/images
grep -v '^\s*#' tests/golden/cases.txt | grep -v '^\s*$' | while read -r name args; do
    # shellcheck disable=SC2086
    "$bin" render $args -W 32 -H 24 -s 8 --threads 2 -o "tests/golden/images/$name.exr" > /dev/null 2>&1
    echo "$name"
done
grep -m1 -o -w 'avx512f\|avx2\|fma\|sse4_2' /proc/cpuinfo > /dev/null
python3 - <<'PY' > tests/golden/cpu.txt
flags = next(l for l in open('/proc/cpuinfo') if l.startswith('flags')).split(':')[1].split()
print(' '.join(f for f in ['sse4_2', 'avx', 'avx2', 'fma', 'avx512f', 'avx512vl'] if f in flags))
PY
