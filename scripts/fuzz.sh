#!/bin/sh
# Builds the libFuzzer targets (tests/fuzz, TC_BUILD_FUZZ) with clang in build-fuzz/ and runs
# each for SECONDS (default 600) at the lowest priority. Crashes land in
# build-fuzz/findings/<target>/ (with log.txt), the corpus grows in build-fuzz/corpus/<target>/.
#   fuzz_case_reader  the case file (toml++, validation, meshes); seeds: tests/cases/**.toml
#   fuzz_gmsh_layer   our half of the .msh reader on arbitrary gmsh arrays; no seeds needed
#   fuzz_gmsh_reader  .msh files through libgmsh (first byte: 0 → 2D, 1 → 3D); seeds:
#                     tests/fuzz/seeds/msh and examples/*/*.msh. libgmsh is not memory-safe on
#                     malformed files (docs/robustness.md), so this one runs with -fork=1 and
#                     keeps going after a crash, collecting them for triage.
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-600}
[ $# -gt 0 ] && shift
targets=${*:-"fuzz_case_reader fuzz_gmsh_layer fuzz_gmsh_reader"}
build=$root/build-fuzz
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-/work} CCACHE_DIR=${CCACHE_DIR:-/work/.ccache}
launcher=""
command -v ccache >/dev/null && launcher="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTC_BUILD_FUZZ=ON -DTC_BUILD_TESTS=OFF -DTC_BUILD_BENCH=OFF $launcher >/dev/null
nice -n 19 cmake --build "$build" -j2 --target $targets

mkdir -p "$build/corpus/fuzz_case_reader" "$build/corpus/fuzz_gmsh_reader" \
  "$build/corpus/fuzz_gmsh_layer"
# Seeds: the case files of tests/cases (the examples' cases build meshes of 10⁴–10⁵ cells,
# too slow under the sanitizers to be useful seeds), the .msh files of tests/fuzz/seeds and of
# examples/ (prefixed by the dimension byte).
find "$root/tests/cases" -name '*.toml' | while read -r f; do
  cp "$f" "$build/corpus/fuzz_case_reader/seed-$(basename "$(dirname "$f")")-$(basename "$f")"
done
cp "$root"/tests/fuzz/seeds/msh/* "$build/corpus/fuzz_gmsh_reader/"
for f in "$root"/examples/*/*.msh; do
  [ -f "$f" ] || continue
  (printf '\000'; cat "$f") >"$build/corpus/fuzz_gmsh_reader/seed-example-$(basename "$f")"
done
export LSAN_OPTIONS="suppressions=$root/tests/fuzz/lsan.supp:print_suppressions=0"
for t in $targets; do
  mkdir -p "$build/findings/$t"
  keep_going=""
  [ "$t" = fuzz_gmsh_reader ] &&
    keep_going="-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1"
  # -rss_limit_mb/-malloc_limit_mb: a case may legally ask for a big mesh; 2 GiB is the
  # budget of one input here. -timeout 60: an input that takes longer is a hang (generous: the machine is shared).
  (cd "$build/findings/$t" && nice -n 19 "$build/bin/$t" "$build/corpus/$t" \
    -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -max_len=100000 -print_final_stats=1 $keep_going -artifact_prefix="$build/findings/$t/" \
    2>&1 | tee "$build/findings/$t/log.txt" | tail -n 30)
done
