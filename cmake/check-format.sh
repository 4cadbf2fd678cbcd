#!/usr/bin/env bash
# Fails (exit 1, naming the files) when a C++ source differs from what the repository's
# .clang-format makes of it. `cmake/check-format.sh --fix` reformats them in place instead.
# Run by cmake/build-and-test.sh (the README's test command) before the build.
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
[[ ${1:-} == --fix ]] && fix=1
command -v clang-format >/dev/null || { echo "check-format: clang-format is not installed (cmake/install-deps.sh)" >&2; exit 2; }
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files -- '*.h' '*.cpp')
else
  mapfile -t files < <(find core geometry render scenes compare app pipeline tests bench fuzz \
                         \( -name '*.h' -o -name '*.cpp' \) 2>/dev/null | sort)
fi
if ((fix)); then
  clang-format -i "${files[@]}"
  exit 0
fi
mapfile -t bad < <(printf '%s\0' "${files[@]}" |
  xargs -0 -P "$(nproc)" -n 16 sh -c 'for f; do clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || echo "$f"; done' _ |
  sort)
if ((${#bad[@]})); then
  echo "check-format: ${#bad[@]} file(s) differ from .clang-format (run cmake/check-format.sh --fix):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files follow .clang-format"
