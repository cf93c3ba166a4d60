#!/usr/bin/env bash
# Fails when a C++ file differs from .clang-format's layout; skipped (exit
# 77) where clang-format is not installed. Run `scripts/check_format.sh
# --fix` to apply it.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
if ! command -v clang-format > /dev/null; then
  echo "skipped: clang-format is not installed (apt install clang-format)"
  exit 77
fi
files=$(git ls-files --cached --others --exclude-standard '*.cc' '*.h' 2> /dev/null || find src apps bench fuzz -name '*.cc' -o -name '*.h')
if [ "${1:-}" = "--fix" ]; then
  echo "$files" | xargs clang-format -i
  exit 0
fi
bad=0
for f in $files; do
  if ! clang-format --dry-run --Werror "$f" > /dev/null 2>&1; then
    echo "$f: not formatted as .clang-format says (scripts/check_format.sh --fix)"
    bad=1
  fi
done
[ "$bad" = 0 ] && echo "all $(echo "$files" | wc -l) C++ files formatted"
exit "$bad"
