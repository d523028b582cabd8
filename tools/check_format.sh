#!/usr/bin/env bash
# Fails, listing the files, when a committed C++ file is not as the
# committed .clang-format (Debian's clang-format 14) would write it.
# Fix with: git ls-files '*.cpp' '*.h' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format >/dev/null; then
  echo "clang-format is not installed (Debian package clang-format)" >&2
  exit 2
fi
bad=$(git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run 2>&1 | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: warning: code should be clang-formatted.*/\1/p' | sort -u)
if [ -n "$bad" ]; then
  echo "These files are not formatted (run: git ls-files '*.cpp' '*.h' | xargs clang-format -i):" >&2
  echo "$bad" >&2
  exit 1
fi
echo "formatting: every C++ file matches .clang-format"
