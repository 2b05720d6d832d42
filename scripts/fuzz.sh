#!/bin/sh
# Builds the libFuzzer targets (tests/fuzz, TC_BUILD_FUZZ) with clang in build-fuzz/ and runs
# each for SECONDS (default 600) at the lowest priority, from the seeds: every case file of
# tests/cases and examples/, and tests/fuzz/seeds/msh (first byte: 0 → 2D, 1 → 3D; then a
# .msh file). Crashes land in build-fuzz/findings/<target>/; the corpus grows in
# build-fuzz/corpus/<target>/. Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-600}
[ $# -gt 0 ] && shift
targets=${*:-"fuzz_case_reader fuzz_gmsh_reader"}
build=$root/build-fuzz
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-/work} CCACHE_DIR=${CCACHE_DIR:-/work/.ccache}
launcher=""
command -v ccache >/dev/null && launcher="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTC_BUILD_FUZZ=ON -DTC_BUILD_TESTS=OFF -DTC_BUILD_BENCH=OFF $launcher >/dev/null
nice -n 19 cmake --build "$build" -j2 --target $targets

mkdir -p "$build/corpus/fuzz_case_reader" "$build/corpus/fuzz_gmsh_reader"
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
  # -rss_limit_mb/-malloc_limit_mb: a case may legally ask for a big mesh; 2 GiB is the
  # budget of one input here. -timeout 10: an input that takes longer is reported as a hang.
  (cd "$build/findings/$t" && nice -n 19 "$build/bin/$t" "$build/corpus/$t" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -max_len=100000 -print_final_stats=1 -artifact_prefix="$build/findings/$t/" \
    2>&1 | tee "$build/findings/$t/log.txt" | tail -n 30)
done
