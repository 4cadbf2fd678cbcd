#!/usr/bin/env bash
# Size limits of the production sources (docs/style.md, "Size"): no .cpp over 600 lines. Functions
# over 100 lines are refused by clang-tidy (readability-function-size in .clang-tidy).
#   cmake/check-sizes.sh        # every .cpp of core geometry render scenes pipeline compare app denoise sensor python
set -euo pipefail
cd "$(dirname "$0")/.."
limit=600
over=$(find core geometry render scenes pipeline compare app denoise sensor python -name '*.cpp' -print0 | xargs -0 wc -l |
       awk -v limit="$limit" '$2 != "total" && $1 > limit { print "  " $2 ": " $1 " lines" }')
if [[ -n "$over" ]]; then
  echo "check-sizes: production .cpp files over $limit lines (split them by concept):" >&2
  echo "$over" >&2
  exit 1
fi
echo "check-sizes: every production .cpp within $limit lines"
