#!/usr/bin/env bash
# Writes tests/fuzz/loader.dict, the fuzzer's dictionary: every element and
# attribute name of the example experiments and the fuzz corpus, and awkward
# values. Run from anywhere after adding examples or corpus files.
set -euo pipefail
cd "$(dirname "$0")/.."
files=(experiments/*.xml tests/fuzz/corpus/*.xml)
{
  echo "# libFuzzer dictionary for loader_fuzzer: the element and attribute names of"
  echo "# the example experiments and tests/fuzz/corpus, and a few awkward values."
  echo "# Written by tools/make_fuzz_dict.sh."
  cat "${files[@]}" | grep -o '<[a-z_0-9-][a-z_0-9-]*' | sort -u | sed 's/.*/"&"/'
  cat "${files[@]}" | grep -o ' [a-z_0-9]*="' | sort -u | sed 's/^ //; s/="$//; s/.*/" &=\\""/'
  for v in nan inf -inf 1e308 -0 0 1e-320 4294967296 18446744073709551616 0,0,0 1,1 '/>' '</' \
           '<!--' '-->' '&amp;' '<?xml version=\"1.0\"?>'; do
    echo "\"$v\""
  done
} > tests/fuzz/loader.dict
echo "wrote tests/fuzz/loader.dict ($(grep -vc '^#' tests/fuzz/loader.dict) entries)"
