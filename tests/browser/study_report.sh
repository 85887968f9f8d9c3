#!/usr/bin/env bash
# The browser test on a real report: a tiny `symphong study` (three variants, two sample counts, plots and
# tables), then tests/browser/test_report_html.py on its report.html in headless Chromium.
# Usage: study_report.sh SYMPHONG_BINARY [--screenshot PNG]
set -euo pipefail
bin=$1
shift
dir=$(mktemp -d "${TMPDIR:-/tmp}/symphong-browser-study.XXXXXX")
trap 'rm -rf "$dir"' EXIT
"$bin" study cornell --estimators cosine,phong,symmetric-mix --spp 4,16 --repeats 3 --width 48 --height 48 \
  --reference-spp 256 --out "$dir/study" --python /usr/bin/python3 >/dev/null
exec /usr/bin/python3 "$(dirname "$0")/test_report_html.py" --report "$dir/study/report.html" "$@"
